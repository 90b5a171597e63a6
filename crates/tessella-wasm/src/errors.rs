//! Errors as JS sees them: one message string, the error and its sources.

use wasm_bindgen::JsError;

/// The start of the message a panic is thrown with (see [`crate::start`]); the JS side
/// recognises it.
pub const PANIC_PREFIX: &str = "tessella panicked (a bug, please report it): ";

/// `err`'s message followed by its sources' where they add something.
pub fn message(err: &dyn std::error::Error) -> String {
    let mut text = err.to_string();
    let mut source = err.source();
    while let Some(s) = source {
        let more = s.to_string();
        if !text.contains(&more) {
            text = format!("{text}: {more}");
        }
        source = s.source();
    }
    text
}

/// A thrown JS `Error` with a message of ours.
pub fn text(message: impl AsRef<str>) -> JsError {
    JsError::new(message.as_ref())
}
