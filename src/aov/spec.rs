//! `NAME=LPE` specifications of AOVs (`raytree render --aov`).

use super::MAX_AOVS;
use crate::lpe::Lpe;

/// One AOV: its name (used in file names) and its compiled expression.
#[derive(Clone, Debug)]
pub struct Aov {
    /// `[A-Za-z0-9_-]+`, not starting with `-`.
    pub name: String,
    /// The light path expression.
    pub lpe: Lpe,
}

/// A bad `NAME=LPE`: which specification (0-based), the 1-based column in it, and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{}: column {column}: {}",
    crate::input::quote(spec),
    crate::input::escape_controls(message)
)]
pub struct AovSpecError {
    /// The specification as written.
    pub spec: String,
    /// 0-based index among the specifications.
    pub index: usize,
    /// 1-based character column in `spec`.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

impl Aov {
    /// Parse `NAME=LPE`.
    ///
    /// # Errors
    /// [`AovSpecError`] (with `index` 0) for a missing `=`, an empty or bad name (column of
    /// the first bad character), or a bad expression (its column, counted in `spec`).
    pub fn parse(spec: &str) -> Result<Self, AovSpecError> {
        let fail = |column, message: String| AovSpecError {
            spec: spec.to_owned(),
            index: 0,
            column,
            message,
        };
        let Some((name, expr)) = spec.split_once('=') else {
            return Err(fail(1, "expected NAME=LPE (e.g. caustics=C<RD>S+L)".into()));
        };
        if name.is_empty() {
            return Err(fail(1, "the AOV name before '=' is empty".into()));
        }
        let ok = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
        if let Some((i, c)) = name
            .chars()
            .enumerate()
            .find(|&(i, c)| !ok(c) || (i == 0 && c == '-'))
        {
            return Err(fail(
                i + 1,
                format!(
                    "'{c}' in the AOV name: names are letters, digits, '_' and '-' (not first), as they name files"
                ),
            ));
        }
        let lpe = Lpe::parse(expr).map_err(|e| {
            fail(
                name.chars().count() + 1 + e.column,
                format!("light path expression: {}", e.message),
            )
        })?;
        Ok(Self {
            name: name.to_owned(),
            lpe,
        })
    }
}

/// Parse every specification; names must be distinct (a duplicate is reported at its name).
///
/// # Errors
/// The first bad specification ([`Aov::parse`]), a duplicate name, or more than
/// [`MAX_AOVS`].
pub fn parse_aovs(specs: &[String]) -> Result<Vec<Aov>, AovSpecError> {
    let mut out: Vec<Aov> = Vec::with_capacity(specs.len());
    for (index, spec) in specs.iter().enumerate() {
        let aov = Aov::parse(spec).map_err(|e| AovSpecError { index, ..e })?;
        let fail = |message: String| AovSpecError {
            spec: spec.clone(),
            index,
            column: 1,
            message,
        };
        if out.iter().any(|a| a.name == aov.name) {
            return Err(fail(format!(
                "the AOV name '{}' is given twice (each names a file)",
                aov.name
            )));
        }
        if out.len() == MAX_AOVS {
            return Err(fail(format!("at most {MAX_AOVS} AOVs")));
        }
        out.push(aov);
    }
    Ok(out)
}
