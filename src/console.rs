//! The program's status lines on stdout and stderr ([`say!`](crate::say) and
//! [`note!`](crate::note)), and the clipping of long values echoed in them ([`clip`]).
//!
//! A line that cannot be written is dropped: stdout or stderr may be a closed pipe (`| head -1`,
//! `| true`, a `tee` that died), and `println!`/`eprintln!` panic then (Rust ignores SIGPIPE), which
//! ended a run before it wrote anything, or a finished one with exit 101. The work, its files and
//! its exit code never depend on whether anyone reads these lines.
//!
//! Where it sits: at the bottom, beside `io` and `math`; every layer that speaks uses it.

use std::borrow::Cow;
use std::fmt::Arguments;
use std::io::Write;

/// Most characters of a value echoed in a message or a status line ([`clip`]).
pub const ECHO_LIMIT: usize = 200;

/// Writes `text` to stdout; a write error (a closed pipe) is ignored.
pub fn stdout(text: Arguments) {
    let _ = std::io::stdout().lock().write_fmt(text);
}

/// Writes `text` to stderr; a write error (a closed pipe) is ignored.
pub fn stderr(text: Arguments) {
    let _ = std::io::stderr().lock().write_fmt(text);
}

/// `println!` that never panics: a line on stdout, dropped if it cannot be written.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::console::stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `eprintln!` that never panics: a line on stderr, dropped if it cannot be written.
#[macro_export]
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::console::stderr(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `text` as echoed in a message: whole up to [`ECHO_LIMIT`] characters, else its first
/// [`ECHO_LIMIT`] characters, an ellipsis and the full length (a 10 MB scene name was echoed
/// whole).
pub fn clip(text: &str) -> Cow<'_, str> {
    match text.char_indices().nth(ECHO_LIMIT) {
        None => Cow::Borrowed(text),
        Some((end, _)) => Cow::Owned(format!(
            "{}... ({} characters)",
            &text[..end],
            text.chars().count()
        )),
    }
}

/// A number as echoed in a message: as written (`0.6`, `60`) between 1e-4 and 1e9 in size, else
/// in scientific notation (`1e300`, `1e-300`): a duration of 1e300 s was echoed as 301 digits.
pub fn num(x: f64) -> String {
    let size = x.abs();
    if size == 0.0 || (1e-4..1e9).contains(&size) || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_echoed_short() {
        assert_eq!(num(0.6), "0.6");
        assert_eq!(num(60.0), "60");
        assert_eq!(num(1e300), "1e300");
        assert_eq!(num(-1e-300), "-1e-300");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(f64::NAN), "NaN");
    }

    #[test]
    fn clip_keeps_short_text_and_cuts_long_text_on_a_character() {
        assert_eq!(clip("sphere"), "sphere");
        let exact = "x".repeat(ECHO_LIMIT);
        assert_eq!(clip(&exact), exact);
        let long = "é".repeat(10_000);
        let clipped = clip(&long);
        assert_eq!(
            clipped,
            format!("{}... (10000 characters)", "é".repeat(ECHO_LIMIT))
        );
    }
}
