//! pbrt-v4 parameter lists: `"type name" value` or `"type name" [values]`, typed and looked up
//! by name; whatever a directive does not read is reported as ignored.

use super::lex::{Tok, Token};

/// One parameter's values.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// Numbers (`integer`, `float`, `point*`, `vector*`, `normal*`, `rgb`, `blackbody`,
    /// `spectrum` given as wavelength-value pairs).
    Nums(Vec<f64>),
    /// Strings (`string`, `texture`, `spectrum` given by name).
    Strs(Vec<String>),
    /// Booleans.
    Bools(Vec<bool>),
}

/// A parameter.
#[derive(Clone, Debug)]
pub struct Param {
    /// Declared type (`float`, `rgb`, ...).
    pub ty: String,
    /// Name.
    pub name: String,
    /// Values.
    pub values: Values,
    /// Where it was declared.
    pub line: usize,
    /// Column.
    pub column: usize,
    /// Whether a directive read it.
    pub used: std::cell::Cell<bool>,
}

const TYPES: [&str; 15] = [
    "integer",
    "float",
    "point2",
    "vector2",
    "point3",
    "vector3",
    "normal3",
    "normal",
    "point",
    "vector",
    "rgb",
    "color",
    "spectrum",
    "blackbody",
    "bool",
];

/// A directive's parameters.
#[derive(Clone, Debug, Default)]
pub struct Params(pub Vec<Param>);

/// A parameter error: position and message.
pub type ParamError = (usize, usize, String);

impl Params {
    /// Read parameters from `toks[*i..]` while the next token is a string.
    ///
    /// # Errors
    /// A malformed declaration, an unknown type, or values of the wrong kind.
    pub fn parse(toks: &[Token], i: &mut usize) -> Result<Params, ParamError> {
        let mut out = Vec::new();
        while let Some(Token {
            tok: Tok::Str(decl),
            line,
            column,
        }) = toks.get(*i)
        {
            let (line, column) = (*line, *column);
            let words: Vec<&str> = decl.split_whitespace().collect();
            let [ty, name] = words[..] else {
                return Err((
                    line,
                    column,
                    format!("expected \"type name\", got {decl:?}"),
                ));
            };
            if !TYPES.contains(&ty) && ty != "string" && ty != "texture" {
                return Err((
                    line,
                    column,
                    format!("unknown parameter type {ty:?} in {decl:?}"),
                ));
            }
            *i += 1;
            let raw = values(toks, i)
                .ok_or_else(|| (line, column, format!("parameter {decl:?} has no value")))?;
            let values = typed(ty, raw).map_err(|m| (line, column, format!("{decl:?}: {m}")))?;
            out.push(Param {
                ty: ty.to_string(),
                name: name.to_string(),
                values,
                line,
                column,
                used: std::cell::Cell::new(false),
            });
        }
        Ok(Params(out))
    }

    /// The parameter `name`, marked as read.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<&Param> {
        let p = self.0.iter().rev().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Names of the parameters nothing read.
    #[must_use]
    pub fn unused(&self) -> Vec<String> {
        self.0
            .iter()
            .filter(|p| !p.used.get())
            .map(|p| format!("\"{} {}\"", p.ty, p.name))
            .collect()
    }
}

/// One value or a bracketed list.
fn values(toks: &[Token], i: &mut usize) -> Option<Vec<Tok>> {
    match &toks.get(*i)?.tok {
        Tok::Open => {
            *i += 1;
            let mut v = Vec::new();
            loop {
                match &toks.get(*i)?.tok {
                    Tok::Close => {
                        *i += 1;
                        return Some(v);
                    }
                    Tok::Open => return None,
                    t => v.push(t.clone()),
                }
                *i += 1;
            }
        }
        t @ (Tok::Num(_) | Tok::Str(_) | Tok::Word(_)) => {
            let t = t.clone();
            *i += 1;
            Some(vec![t])
        }
        Tok::Close => None,
    }
}

fn typed(ty: &str, raw: Vec<Tok>) -> Result<Values, String> {
    match ty {
        "string" | "texture" => raw
            .into_iter()
            .map(|t| match t {
                Tok::Str(s) => Ok(s),
                other => Err(format!("expected strings, got {other:?}")),
            })
            .collect::<Result<_, _>>()
            .map(Values::Strs),
        "bool" => raw
            .into_iter()
            .map(|t| match t {
                Tok::Str(s) | Tok::Word(s) if s == "true" => Ok(true),
                Tok::Str(s) | Tok::Word(s) if s == "false" => Ok(false),
                other => Err(format!("expected true or false, got {other:?}")),
            })
            .collect::<Result<_, _>>()
            .map(Values::Bools),
        "spectrum" if matches!(raw.first(), Some(Tok::Str(_))) => typed("string", raw),
        _ => raw
            .into_iter()
            .map(|t| match t {
                Tok::Num(v) => Ok(v),
                other => Err(format!("expected numbers, got {other:?}")),
            })
            .collect::<Result<_, _>>()
            .map(Values::Nums),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::pbrt::lex::tokens;

    #[test]
    fn typed_parameters_and_errors() {
        let t = tokens(
            "\"float fov\" 45 \"rgb L\" [1 2 3] \"bool twosided\" true \"string s\" \"x\" Shape",
        )
        .unwrap();
        let mut i = 0;
        let p = Params::parse(&t, &mut i).unwrap();
        assert_eq!(p.0.len(), 4);
        assert_eq!(t[i].tok, Tok::Word("Shape".into()));
        assert_eq!(
            p.get("L").unwrap().values,
            Values::Nums(vec![1.0, 2.0, 3.0])
        );
        assert_eq!(p.get("twosided").unwrap().values, Values::Bools(vec![true]));
        assert_eq!(p.unused(), vec!["\"float fov\"", "\"string s\""]);
        for bad in [
            "\"float\" 1",
            "\"floot x\" 1",
            "\"float x\" \"a\"",
            "\"float x\" [1",
        ] {
            let t = tokens(bad).unwrap();
            assert!(Params::parse(&t, &mut 0).is_err(), "{bad}");
        }
    }
}
