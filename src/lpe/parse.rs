//! The LPE parser: characters to [`Ast`], with the column of the first error.

use super::{ALL, Ast, LpeError, SCATTERS, TYPES};

/// Largest repetition bound accepted in `{n,m}`.
const MAX_REPEAT: u32 = 1000;
/// Deepest nesting of `(` accepted (the parser recurses on groups).
const MAX_NEST: usize = 64;

/// Parse a whole expression.
pub(super) fn parse(expr: &str) -> Result<Ast, LpeError> {
    let mut p = Parser {
        chars: expr.chars().collect(),
        pos: 0,
        depth: 0,
    };
    p.skip_space();
    if p.peek().is_none() {
        return Err(p.err("the expression is empty"));
    }
    let ast = p.alternation()?;
    match p.peek() {
        None => Ok(ast),
        Some(')') => Err(p.err("')' without a matching '('")),
        Some(c) => Err(p.err(&format!("unexpected '{c}'"))),
    }
}

/// The events of a type letter (any scattering) or a scattering letter (any type).
fn letter_set(c: char) -> Option<u32> {
    if let Some(t) = TYPES.iter().position(|x| *x == c) {
        return Some(0b1111 << (t * 4));
    }
    let s = 1 + SCATTERS.iter().position(|x| *x == c)?;
    Some((0..TYPES.len()).fold(0, |acc, t| acc | 1 << (t * 4 + s)))
}

struct Parser {
    chars: Vec<char>,
    pos: usize,
    /// Open groups around the current position.
    depth: usize,
}

impl Parser {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.pos).copied()
    }

    fn skip_space(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.pos += 1;
        }
    }

    /// The next non-space character, consumed.
    fn bump(&mut self) -> Option<char> {
        let c = self.peek();
        if c.is_some() {
            self.pos += 1;
        }
        self.skip_space();
        c
    }

    fn err(&self, message: &str) -> LpeError {
        self.err_at(self.pos, message)
    }

    fn err_at(&self, pos: usize, message: &str) -> LpeError {
        LpeError {
            column: pos + 1,
            message: message.to_owned(),
        }
    }

    fn alternation(&mut self) -> Result<Ast, LpeError> {
        let mut items = vec![self.concat()?];
        while self.peek() == Some('|') {
            self.bump();
            items.push(self.concat()?);
        }
        Ok(if items.len() == 1 {
            items.remove(0)
        } else {
            Ast::Alt(items)
        })
    }

    fn concat(&mut self) -> Result<Ast, LpeError> {
        let mut items = Vec::new();
        while let Some(c) = self.peek() {
            if c == '|' || c == ')' {
                break;
            }
            items.push(self.repeat()?);
        }
        if items.is_empty() {
            return Err(self.err(match self.peek() {
                None => "the expression ends where an event was expected",
                Some(_) => "an event was expected here",
            }));
        }
        Ok(if items.len() == 1 {
            items.remove(0)
        } else {
            Ast::Concat(items)
        })
    }

    fn repeat(&mut self) -> Result<Ast, LpeError> {
        let mut ast = self.atom()?;
        loop {
            let (min, max) = match self.peek() {
                Some('*') => (0, None),
                Some('+') => (1, None),
                Some('?') => (0, Some(1)),
                Some('{') => {
                    let (min, max) = self.bounds()?;
                    ast = Ast::Repeat(Box::new(ast), min, max);
                    continue;
                }
                _ => return Ok(ast),
            };
            self.bump();
            ast = Ast::Repeat(Box::new(ast), min, max);
        }
    }

    /// `{n}`, `{n,}` or `{n,m}`.
    fn bounds(&mut self) -> Result<(u32, Option<u32>), LpeError> {
        let open = self.pos;
        self.bump();
        let min = self.number()?;
        let max = match self.bump() {
            Some('}') => return Ok((min, Some(min))),
            Some(',') if self.peek() == Some('}') => {
                self.bump();
                return Ok((min, None));
            }
            Some(',') => self.number()?,
            _ => {
                return Err(self.err_at(self.pos.saturating_sub(1), "expected ',' or '}'"));
            }
        };
        if self.bump() != Some('}') {
            return Err(self.err_at(self.pos.saturating_sub(1), "expected '}'"));
        }
        if min > max {
            return Err(self.err_at(open, &format!("repetition {{{min},{max}}}: {min} > {max}")));
        }
        Ok((min, Some(max)))
    }

    fn number(&mut self) -> Result<u32, LpeError> {
        let start = self.pos;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.pos += 1;
        }
        let digits: String = self.chars[start..self.pos].iter().collect();
        self.skip_space();
        match digits.parse::<u32>() {
            Ok(n) if n <= MAX_REPEAT => Ok(n),
            Ok(_) | Err(_) if !digits.is_empty() => Err(self.err_at(
                start,
                &format!("repetition bound {digits} is above {MAX_REPEAT}"),
            )),
            _ => Err(self.err_at(start, "expected a number")),
        }
    }

    fn atom(&mut self) -> Result<Ast, LpeError> {
        let at = self.pos;
        match self.peek() {
            Some('(') => {
                self.bump();
                if self.peek() == Some(')') {
                    return Err(self.err("empty group '()'"));
                }
                if self.depth >= MAX_NEST {
                    return Err(self.err_at(at, &format!("groups nest deeper than {MAX_NEST}")));
                }
                self.depth += 1;
                let inner = self.alternation()?;
                self.depth -= 1;
                if self.bump() != Some(')') {
                    return Err(self.err_at(at, "'(' is never closed"));
                }
                Ok(inner)
            }
            Some('[') => {
                self.bump();
                let negate = self.peek() == Some('^');
                if negate {
                    self.bump();
                }
                let mut bits = 0;
                loop {
                    match self.peek() {
                        None => return Err(self.err_at(at, "'[' is never closed")),
                        Some(']') => break,
                        Some(_) => bits |= self.event()?,
                    }
                }
                if bits == 0 && !negate {
                    return Err(self.err("empty set '[]'"));
                }
                self.bump();
                Ok(Ast::Set(if negate { ALL & !bits } else { bits }))
            }
            _ => Ok(Ast::Set(self.event()?)),
        }
    }

    /// One event: a letter, `.` or `<type scattering 'label'>`.
    fn event(&mut self) -> Result<u32, LpeError> {
        let at = self.pos;
        match self.bump() {
            Some('.') => Ok(ALL),
            Some('<') => self.explicit(at),
            Some(c) if c.is_alphabetic() => letter_set(c).ok_or_else(|| {
                self.err_at(
                    at,
                    &format!(
                        "unknown event '{c}' (types C R T V L O B, scatterings D G S, or '.')"
                    ),
                )
            }),
            Some(c) => Err(self.err_at(at, &format!("an event was expected, not '{c}'"))),
            None => Err(self.err_at(at, "the expression ends where an event was expected")),
        }
    }

    /// The rest of `<type scattering 'label'>` (fields after the first may be left out).
    fn explicit(&mut self, open: usize) -> Result<u32, LpeError> {
        let mut bits = ALL;
        for field in 0..3 {
            let at = self.pos;
            match self.peek() {
                Some('>') if field > 0 => break,
                None => return Err(self.err_at(open, "'<' is never closed")),
                Some('.') => {
                    self.bump();
                }
                Some('\'') if field == 2 => {
                    self.pos += 1;
                    let start = self.pos;
                    while self.peek().is_some_and(|c| c != '\'') {
                        self.pos += 1;
                    }
                    if self.peek().is_none() {
                        return Err(self.err_at(at, "the label's quote is never closed"));
                    }
                    let empty = self.pos == start;
                    self.bump();
                    // raytree records no labels: only the empty label matches.
                    if !empty {
                        bits = 0;
                    }
                }
                Some(c) => {
                    let set = match field {
                        0 if TYPES.contains(&c) => letter_set(c),
                        1 if SCATTERS.contains(&c) => letter_set(c),
                        _ => None,
                    };
                    let Some(set) = set else {
                        let what = ["a type (C R T V L O B)", "a scattering (D G S)", "a label"];
                        return Err(
                            self.err_at(at, &format!("expected {} or '.', not '{c}'", what[field]))
                        );
                    };
                    bits &= set;
                    self.bump();
                }
            }
        }
        match self.bump() {
            Some('>') => Ok(bits),
            None => Err(self.err_at(open, "'<' is never closed")),
            Some(c) => Err(self.err_at(
                self.pos.saturating_sub(1),
                &format!("expected '>', not '{c}'"),
            )),
        }
    }
}
