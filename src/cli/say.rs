//! Writing to standard output and error without panicking when they are closed or full.

use std::io::Write;

/// Standard output could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write to standard output: {0}")]
pub struct StdoutError(pub std::io::Error);

impl StdoutError {
    /// The reader went away (`| head`): not an error of ours, so exit quietly.
    pub fn is_broken_pipe(&self) -> bool {
        self.0.kind() == std::io::ErrorKind::BrokenPipe
    }
}

/// Write `s` to standard output and flush.
pub fn out(s: &str) -> Result<(), StdoutError> {
    let s = raytree::text::guard_nonfinite(s);
    let mut o = std::io::stdout().lock();
    o.write_all(s.as_bytes())
        .and_then(|()| o.flush())
        .map_err(StdoutError)
}

/// Write `v` as pretty JSON and a newline to standard output, streamed (the text is never held
/// whole: a recorded tree's JSON is several times the tree).
pub fn json<T: serde::Serialize + ?Sized>(v: &T) -> Result<(), StdoutError> {
    let mut o = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
    serde_json::to_writer_pretty(&mut o, v)
        .map_err(std::io::Error::from)
        .and_then(|()| o.write_all(b"\n"))
        .and_then(|()| o.flush())
        .map_err(StdoutError)
}

/// Write `s` to standard error; if that fails there is nowhere left to report it.
pub fn err(s: &str) {
    let s = raytree::text::guard_nonfinite(s);
    let _ = std::io::stderr().lock().write_all(s.as_bytes());
}

/// `println!` that returns a [`StdoutError`] instead of panicking.
macro_rules! sayln {
    ($($t:tt)*) => { $crate::cli::say::out(&format!("{}\n", format_args!($($t)*))) };
}
/// `eprintln!` that never panics.
macro_rules! warnln {
    ($($t:tt)*) => { $crate::cli::say::err(&format!("{}\n", format_args!($($t)*))) };
}
pub(crate) use {sayln, warnln};
