//! Writing a file so that readers see either the old file or the complete new one.

use crate::IoError;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Writes `path` through `write`: the bytes go to a temporary file in the same folder, which is
/// renamed over `path` only when everything succeeded (renames within one folder are atomic).
///
/// On any error (the closure's, flushing, or the rename) the temporary file is removed and
/// `path` is left as it was: absent, or holding its old contents.
///
/// ```
/// # let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("hello.txt");
/// tessella_io::write_atomic(&path, |w| w.write_all(b"hello"))?;
/// assert_eq!(std::fs::read(&path).unwrap(), b"hello");
/// # Ok::<(), tessella_io::IoError>(())
/// ```
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    let failed = |source| IoError::Write {
        path: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".tessella-").suffix(".tmp");
    // NamedTempFile defaults to 0600; 0666 minus the umask is what a plain create would give.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let temp = builder.tempfile_in(dir).map_err(failed)?;
    let mut out = BufWriter::new(temp);
    write(&mut out).map_err(failed)?;
    let temp = out.into_inner().map_err(|e| failed(e.into_error()))?;
    temp.as_file().sync_all().map_err(failed)?;
    // Dropping the returned temp file (inside the error) deletes it.
    temp.persist(path).map_err(|e| failed(e.error))?;
    Ok(())
}
