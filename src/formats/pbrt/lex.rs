//! pbrt-v4's tokens: bare words (directives, `true`/`false`), quoted strings, numbers and
//! brackets; `#` comments to the end of the line. Each token keeps its line and column.

/// One token.
#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    /// A bare word: a directive name or `true`/`false`.
    Word(String),
    /// A quoted string (escapes resolved).
    Str(String),
    /// A number.
    Num(f64),
    /// `[`.
    Open,
    /// `]`.
    Close,
}

/// A token and where it starts (1-based).
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// The token.
    pub tok: Tok,
    /// Line.
    pub line: usize,
    /// Column (characters).
    pub column: usize,
}

/// The tokens of `src`, or the position and reason of the first bad one.
///
/// # Errors
/// An unterminated string, a bad escape, or a character that starts no token.
pub fn tokens(src: &str) -> Result<Vec<Token>, (usize, usize, String)> {
    let mut out = Vec::new();
    let mut it = src.char_indices().peekable();
    let (mut line, mut line_start) = (1usize, 0usize);
    while let Some(&(i, c)) = it.peek() {
        let column = src[line_start..i].chars().count() + 1;
        let at = |tok| Token { tok, line, column };
        match c {
            '\n' => {
                it.next();
                line += 1;
                line_start = i + 1;
            }
            c if c.is_whitespace() => {
                it.next();
            }
            '#' => {
                while it.peek().is_some_and(|&(_, c)| c != '\n') {
                    it.next();
                }
            }
            '[' => {
                it.next();
                out.push(at(Tok::Open));
            }
            ']' => {
                it.next();
                out.push(at(Tok::Close));
            }
            '"' => {
                it.next();
                let mut s = String::new();
                loop {
                    match it.next() {
                        None | Some((_, '\n')) => {
                            return Err((line, column, "unterminated string".into()));
                        }
                        Some((_, '"')) => break,
                        Some((_, '\\')) => match it.next() {
                            Some((_, 'n')) => s.push('\n'),
                            Some((_, 't')) => s.push('\t'),
                            Some((_, c @ ('\\' | '"' | '\''))) => s.push(c),
                            _ => return Err((line, column, "bad escape in string".into())),
                        },
                        Some((_, c)) => s.push(c),
                    }
                }
                out.push(at(Tok::Str(s)));
            }
            _ => {
                let start = i;
                let mut end = i;
                while let Some(&(j, c)) = it.peek() {
                    if c.is_whitespace() || matches!(c, '[' | ']' | '"' | '#') {
                        break;
                    }
                    end = j + c.len_utf8();
                    it.next();
                }
                let w = &src[start..end];
                let tok = if w.starts_with(|c: char| c.is_ascii_digit() || "+-.".contains(c)) {
                    match w.parse::<f64>() {
                        Ok(v) if v.is_finite() => Tok::Num(v),
                        _ => return Err((line, column, format!("bad number {w:?}"))),
                    }
                } else if w.starts_with(|c: char| c.is_ascii_alphabetic()) {
                    Tok::Word(w.to_string())
                } else {
                    return Err((line, column, format!("unexpected {w:?}")));
                };
                out.push(at(tok));
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_with_positions() {
        let t = tokens("Shape \"sphere\" # c\n  \"float radius\" [ 2.5 ]").unwrap();
        assert_eq!(t[0].tok, Tok::Word("Shape".into()));
        assert_eq!(t[1].tok, Tok::Str("sphere".into()));
        assert_eq!((t[2].line, t[2].column), (2, 3));
        assert_eq!(t[4].tok, Tok::Num(2.5));
        assert_eq!(t[5].tok, Tok::Close);
        assert_eq!(tokens("\"abc").unwrap_err().0, 1);
        assert!(tokens("1e999").is_err());
        assert!(tokens("Shape @").unwrap_err().2.contains("unexpected"));
    }
}
