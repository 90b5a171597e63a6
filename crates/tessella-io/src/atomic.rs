//! Writing a file so that readers see either the old file or the complete new one, and a
//! process killed while writing leaves nothing behind.

use crate::IoError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Whether a finished file is flushed to the disk before it is put in place.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Durability {
    /// `fsync` before the file gets its name: after a power cut the name holds the whole file
    /// or the old one.
    #[default]
    Synced,
    /// The name is given as soon as the bytes are in the system's cache. A killed process
    /// still leaves either the whole file or nothing (the kernel keeps the cache); only a power
    /// cut before the cache reaches the disk can lose it. For many files at once, whose caller
    /// flushes them together afterwards ([`sync_folder`]) instead of one `fsync` each.
    Cached,
}

impl Durability {
    /// [`Durability::Synced`] when `sync`, else [`Durability::Cached`].
    ///
    /// ```
    /// use tessella_io::Durability;
    /// assert_eq!(Durability::synced_if(true), Durability::Synced);
    /// assert_eq!(Durability::synced_if(false), Durability::Cached);
    /// ```
    pub fn synced_if(sync: bool) -> Durability {
        match sync {
            true => Durability::Synced,
            false => Durability::Cached,
        }
    }
}

/// Writes `path` through `write`: the bytes go to a file without a name in the same folder
/// (Linux's `O_TMPFILE`), which is given `path`'s name only when everything succeeded, so a
/// process killed half-way, even by SIGKILL, leaves no file behind. Where the system has no
/// unnamed files (other platforms, file systems without `O_TMPFILE`, no `/proc`), a named
/// temporary file `.tessella-*.tmp` in the same folder is renamed instead; that one is
/// removed on any error but stays behind if the process is killed.
///
/// On any error (the closure's, flushing, or the rename) `path` is left as it was: absent, or
/// holding its old contents. The file is `fsync`ed first ([`Durability::Synced`]).
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
    write_atomic_with(path, Durability::Synced, write)
}

/// [`write_atomic`] with a choice of whether the file is flushed to the disk first.
pub fn write_atomic_with(
    path: &Path,
    durability: Durability,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), IoError> {
    let failed = |source| IoError::Write {
        path: path.to_path_buf(),
        source,
    };
    let dir = folder_of(path);
    #[cfg(target_os = "linux")]
    if let Some(file) = unnamed::create(dir) {
        let file = fill(file, durability, write, |f| f).map_err(failed)?;
        // Dropped without a name on any error: the kernel frees it.
        return unnamed::publish(&file, dir, path).map_err(failed);
    }
    let mut builder = tempfile::Builder::new();
    builder.prefix(TEMP_PREFIX).suffix(TEMP_SUFFIX);
    // NamedTempFile defaults to 0600; 0666 minus the umask is what a plain create would give.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let temp = builder.tempfile_in(dir).map_err(failed)?;
    let temp = fill(temp, durability, write, |t| t.as_file()).map_err(failed)?;
    // Dropping the returned temp file (inside the error) deletes it.
    temp.persist(path).map_err(|e| failed(e.error))?;
    Ok(())
}

/// Writes `target` through `write`, buffered, and flushes it to the disk when `durability`
/// says so; `file` gives the [`File`] to flush. Returns the target for naming.
fn fill<W: Write>(
    target: W,
    durability: Durability,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
    file: impl Fn(&W) -> &File,
) -> std::io::Result<W> {
    let mut out = BufWriter::new(target);
    write(&mut out)?;
    let target = out.into_inner().map_err(|e| e.into_error())?;
    if durability == Durability::Synced {
        file(&target).sync_all()?;
    }
    Ok(target)
}

/// Flushes every file of the file system that holds `dir` to the disk (Linux's `syncfs`;
/// elsewhere a `sync_all` of the folder itself). The one flush that follows many
/// [`Durability::Cached`] writes.
pub fn sync_folder(dir: &Path) -> Result<(), IoError> {
    let failed = |source| IoError::Write {
        path: dir.to_path_buf(),
        source,
    };
    let folder = File::open(dir).map_err(failed)?;
    #[cfg(target_os = "linux")]
    {
        rustix::fs::syncfs(&folder).map_err(|e| failed(e.into()))
    }
    #[cfg(not(target_os = "linux"))]
    {
        folder.sync_all().map_err(failed)
    }
}

/// The name prefix and suffix of the named temporary files (the fallback), so a batch can find
/// and remove the ones a killed run left.
pub const TEMP_PREFIX: &str = ".tessella-";
pub const TEMP_SUFFIX: &str = ".tmp";

fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

#[cfg(target_os = "linux")]
mod unnamed {
    use super::{TEMP_PREFIX, TEMP_SUFFIX};
    use rustix::fs::{AtFlags, Mode, OFlags, CWD};
    use rustix::io::Errno;
    use std::fs::File;
    use std::os::fd::AsRawFd;
    use std::path::{Path, PathBuf};

    /// An unnamed file in `dir`, or `None` where the kernel or file system has none, or where
    /// there is no /proc to give it a name through: the named fallback is used then.
    pub fn create(dir: &Path) -> Option<File> {
        if !Path::new("/proc/self/fd").is_dir() {
            return None;
        }
        let flags = OFlags::TMPFILE | OFlags::WRONLY | OFlags::CLOEXEC;
        let fd = rustix::fs::open(dir, flags, Mode::from_raw_mode(0o666)).ok()?;
        Some(File::from(fd))
    }

    /// A name in `dir` for a file that exists for an instant between its link and its rename.
    fn temporary_name(dir: &Path, attempt: u32) -> PathBuf {
        use std::sync::atomic::{AtomicU64, Ordering};
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        dir.join(format!(
            "{TEMP_PREFIX}{}-{n}-{attempt}{TEMP_SUFFIX}",
            std::process::id()
        ))
    }

    fn proc_path(file: &File) -> String {
        format!("/proc/self/fd/{}", file.as_raw_fd())
    }

    fn link(file: &File, to: &Path) -> rustix::io::Result<()> {
        rustix::fs::linkat(CWD, proc_path(file), CWD, to, AtFlags::SYMLINK_FOLLOW)
    }

    /// Gives `file` the name `path`: linked there at once when `path` does not exist (the file
    /// appears whole), else linked to a temporary name and renamed over `path`.
    pub fn publish(file: &File, dir: &Path, path: &Path) -> std::io::Result<()> {
        match link(file, path) {
            Ok(()) => return Ok(()),
            Err(Errno::EXIST) => {}
            Err(e) => return Err(e.into()),
        }
        for attempt in 0..100 {
            let temp = temporary_name(dir, attempt);
            match link(file, &temp) {
                Ok(()) => {
                    let Err(e) = std::fs::rename(&temp, path) else {
                        return Ok(());
                    };
                    return Err(match std::fs::remove_file(&temp) {
                        Ok(()) => e,
                        Err(left) => std::io::Error::new(
                            e.kind(),
                            format!("{e} (and {} stays behind: {left})", temp.display()),
                        ),
                    });
                }
                Err(Errno::EXIST) => continue,
                Err(e) => return Err(e.into()),
            }
        }
        Err(std::io::Error::other(
            "no free temporary name in the folder",
        ))
    }
}
