//! Light path expressions (LPE), OSL's grammar (OpenShadingLanguage `lpeparse.cpp`), matched
//! against the `lpe` strings the path tracer records ([`crate::tree::PathInfo::lpe`]).
//!
//! An event is a pair (type, scattering): type `C` camera, `R` reflection, `T` transmission,
//! `V` volume, `L` light, `O` object emission, `B` background; scattering `D` diffuse, `G`
//! glossy, `S` singular, or none (camera, lights, background). Each of the 28 pairs is one byte,
//! and an expression is compiled once to an anchored byte regex (`regex-automata`'s meta
//! regex) over those bytes. See `docs/path-tracing.md` for the grammar.

mod filter;
mod parse;
#[cfg(test)]
mod tests;

pub use filter::{LpeFilter, filter_tree, filter_tree_all_samples};

use regex_automata::meta::Regex;
use regex_automata::util::syntax;

/// Event types, in byte order.
const TYPES: [char; 7] = ['C', 'R', 'T', 'V', 'L', 'O', 'B'];
/// Scatterings, in byte order (index 0 is "none").
const SCATTERS: [char; 3] = ['D', 'G', 'S'];
/// Number of distinct events.
const EVENTS: u32 = (TYPES.len() * (SCATTERS.len() + 1)) as u32;
/// Every event (a bit per event byte).
const ALL: u32 = (1 << EVENTS) - 1;

/// One recorded event: its type letter and scattering letter (none for `C`, `L`, `B`, `O`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Event {
    /// `C`, `R`, `T`, `V`, `L`, `O` or `B`.
    pub kind: char,
    /// `D`, `G`, `S`, or none.
    pub scatter: Option<char>,
}

impl Event {
    /// The event's byte in the compiled alphabet, if its letters are known.
    fn byte(self) -> Option<u8> {
        let t = TYPES.iter().position(|c| *c == self.kind)?;
        let s = match self.scatter {
            None => 0,
            Some(c) => 1 + SCATTERS.iter().position(|x| *x == c)?,
        };
        u8::try_from(t * (SCATTERS.len() + 1) + s).ok()
    }
}

/// Split a recorded LPE string (`C<RD><TS>L`, `CB`) into its events: a bare letter is an event
/// without scattering, `<XY>` an event of type `X` and scattering `Y`. `None` if the string is
/// not of that form.
#[must_use]
pub fn recorded_events(recorded: &str) -> Option<Vec<Event>> {
    let mut out = Vec::new();
    let mut chars = recorded.chars();
    while let Some(c) = chars.next() {
        let e = if c == '<' {
            let (kind, scatter, close) = (chars.next()?, chars.next()?, chars.next()?);
            (close == '>').then_some(Event {
                kind,
                scatter: Some(scatter),
            })?
        } else {
            Event {
                kind: c,
                scatter: None,
            }
        };
        e.byte()?;
        out.push(e);
    }
    Some(out)
}

/// The bytes of a recorded string, `None` if it holds an unknown event.
fn recorded_bytes(recorded: &str) -> Option<Vec<u8>> {
    recorded_events(recorded)?
        .into_iter()
        .map(Event::byte)
        .collect()
}

/// A bad expression: the 1-based column (in characters) where it goes wrong, and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("light path expression, column {column}: {message}")]
pub struct LpeError {
    /// 1-based character column.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

/// A compiled light path expression.
#[derive(Clone, Debug)]
pub struct Lpe {
    source: String,
    regex: Regex,
}

impl Lpe {
    /// Parse and compile `expr`.
    ///
    /// # Errors
    /// [`LpeError`] with the column of the first problem (unknown letter, unclosed `<`, `[` or
    /// `(`, a repetition `{n,m}` with `n > m`, an empty expression, ...).
    pub fn parse(expr: &str) -> Result<Self, LpeError> {
        let ast = parse::parse(expr)?;
        let mut pattern = String::from(r"\A(?:");
        ast.write_regex(&mut pattern);
        pattern.push_str(r")\z");
        let regex = Regex::builder()
            .syntax(
                syntax::Config::new()
                    .unicode(false)
                    .utf8(false)
                    .nest_limit(1000),
            )
            .build(&pattern)
            .map_err(|e| LpeError {
                column: 1,
                message: format!("the expression is too large to compile ({e})"),
            })?;
        Ok(Self {
            source: expr.to_owned(),
            regex,
        })
    }

    /// The expression as written.
    #[must_use]
    pub fn as_str(&self) -> &str {
        &self.source
    }

    /// Whether the whole recorded string `recorded` (e.g. `C<RD><TS>L`) matches. A string with
    /// an event outside the alphabet matches nothing.
    #[must_use]
    pub fn matches(&self, recorded: &str) -> bool {
        recorded_bytes(recorded).is_some_and(|b| self.regex.is_match(&b[..]))
    }
}

/// The expression tree.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Ast {
    /// One event out of a set (a bit per event byte).
    Set(u32),
    Concat(Vec<Ast>),
    Alt(Vec<Ast>),
    Repeat(Box<Ast>, u32, Option<u32>),
}

impl Ast {
    fn write_regex(&self, out: &mut String) {
        use std::fmt::Write as _;
        match self {
            Self::Set(0) => out.push_str(r"[^\x00-\xFF]"),
            Self::Set(bits) => {
                out.push('[');
                for b in 0..EVENTS {
                    if bits & (1 << b) != 0 {
                        let _ = write!(out, r"\x{b:02X}");
                    }
                }
                out.push(']');
            }
            Self::Concat(items) => {
                out.push_str("(?:");
                for i in items {
                    i.write_regex(out);
                }
                out.push(')');
            }
            Self::Alt(items) => {
                out.push_str("(?:");
                for (k, i) in items.iter().enumerate() {
                    if k > 0 {
                        out.push('|');
                    }
                    i.write_regex(out);
                }
                out.push(')');
            }
            Self::Repeat(inner, min, max) => {
                out.push_str("(?:");
                inner.write_regex(out);
                match max {
                    Some(m) => {
                        let _ = write!(out, "){{{min},{m}}}");
                    }
                    None => {
                        let _ = write!(out, "){{{min},}}");
                    }
                }
            }
        }
    }
}
