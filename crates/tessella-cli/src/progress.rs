//! Progress bars on stderr for long work; silent when stderr is not a terminal, and while a
//! batch draws its own bar ([`quiet`]).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set by `batch`: its per-file refinements draw no bars of their own.
static QUIET: AtomicBool = AtomicBool::new(false);

/// Hides every later [`bar`] and [`byte_bar`] of this process.
pub fn quiet() {
    QUIET.store(true, Ordering::Relaxed);
}

/// Whether bars are drawn: stderr is a terminal and no batch is running.
pub fn shown() -> bool {
    std::io::stderr().is_terminal() && !QUIET.load(Ordering::Relaxed)
}

/// A bar of `total` steps labelled `what`, hidden when stderr is not a terminal.
pub fn bar(total: u64, what: &str) -> ProgressBar {
    styled(total, what, "{msg:>10} [{bar:40}] {percent:>3}% {elapsed}")
}

/// A bar of `total` bytes with throughput and time left.
pub fn byte_bar(total: u64, what: &str) -> ProgressBar {
    styled(
        total,
        what,
        "{msg:>10} [{bar:40}] {bytes}/{total_bytes} {bytes_per_sec} eta {eta}",
    )
}

fn styled(total: u64, what: &str, template: &str) -> ProgressBar {
    if !shown() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template(template)
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}
