//! pbrt's tokens: quoted strings (with `\` escapes), numbers, `[` and `]`, bare words
//! (directive names, `true`/`false`) and `#` comments to the end of the line. Every token keeps
//! its 1-based line and column (in characters) for error messages.

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    /// A quoted string, escapes resolved.
    Str(String),
    /// A number (pbrt's `float` and `integer` values alike).
    Num(f64),
    Open,
    Close,
    /// A bare word: a directive, or `true`/`false`.
    Word(String),
}

/// A token and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Token {
    pub tok: Tok,
    pub line: usize,
    pub col: usize,
}

impl Token {
    /// How the token reads in an error message.
    pub fn describe(&self) -> String {
        match &self.tok {
            Tok::Str(s) => format!("the string \"{}\"", clip(s)),
            Tok::Num(x) => format!("the number {x}"),
            Tok::Open => "'['".to_string(),
            Tok::Close => "']'".to_string(),
            Tok::Word(w) => format!("'{}'", clip(w)),
        }
    }
}

/// At most 40 characters of `s` (messages stay short for long or binary input).
pub(crate) fn clip(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(40).collect();
        t.push('…');
        t
    }
}

/// A tokenizer error: line, column and message.
#[derive(Debug, PartialEq)]
pub(crate) struct TokenError {
    pub line: usize,
    pub col: usize,
    pub message: String,
}

/// Splits `text` into tokens.
pub(crate) fn tokenize(text: &str) -> Result<Vec<Token>, TokenError> {
    let mut out = Vec::new();
    let mut it = text.chars().peekable();
    let (mut line, mut col) = (1usize, 1usize);
    // Advances over one character, keeping line and column.
    macro_rules! bump {
        () => {{
            let c = it.next();
            if c == Some('\n') {
                line += 1;
                col = 1;
            } else if c.is_some() {
                col += 1;
            }
            c
        }};
    }
    while let Some(&c) = it.peek() {
        let (l0, c0) = (line, col);
        match c {
            c if c.is_whitespace() => {
                bump!();
            }
            '#' => {
                while let Some(&c) = it.peek() {
                    if c == '\n' {
                        break;
                    }
                    bump!();
                }
            }
            '[' | ']' => {
                bump!();
                out.push(Token {
                    tok: if c == '[' { Tok::Open } else { Tok::Close },
                    line: l0,
                    col: c0,
                });
            }
            '"' => {
                bump!();
                let mut s = String::new();
                loop {
                    match bump!() {
                        None => {
                            return Err(TokenError {
                                line: l0,
                                col: c0,
                                message: "unterminated string (expected a closing '\"')"
                                    .to_string(),
                            });
                        }
                        Some('\n') => {
                            return Err(TokenError {
                                line: l0,
                                col: c0,
                                message: "unterminated string: a newline before the closing '\"'"
                                    .to_string(),
                            });
                        }
                        Some('"') => break,
                        Some('\\') => {
                            let (l1, c1) = (line, col);
                            let e = match bump!() {
                                Some('n') => '\n',
                                Some('t') => '\t',
                                Some('r') => '\r',
                                Some('b') => '\u{8}',
                                Some('f') => '\u{c}',
                                Some(c @ ('\\' | '\'' | '"')) => c,
                                other => {
                                    return Err(TokenError {
                                        line: l1,
                                        col: c1.saturating_sub(1).max(1),
                                        message: format!(
                                            "unknown escape sequence '\\{}' in a string (expected \\n, \\t, \\\\ or \\\")",
                                            other.map_or_else(String::new, String::from)
                                        ),
                                    });
                                }
                            };
                            s.push(e);
                        }
                        Some(c) => s.push(c),
                    }
                }
                out.push(Token {
                    tok: Tok::Str(s),
                    line: l0,
                    col: c0,
                });
            }
            _ => {
                let mut w = String::new();
                while let Some(&c) = it.peek() {
                    if c.is_whitespace() || matches!(c, '"' | '[' | ']' | '#') {
                        break;
                    }
                    w.push(c);
                    bump!();
                }
                let first = w.chars().next().unwrap_or(' ');
                let tok = if first.is_ascii_digit() || matches!(first, '-' | '+' | '.') {
                    let x: f64 = w.parse().map_err(|_| TokenError {
                        line: l0,
                        col: c0,
                        message: format!("bad number '{}'", clip(&w)),
                    })?;
                    if !x.is_finite() {
                        return Err(TokenError {
                            line: l0,
                            col: c0,
                            message: format!("number must be finite, got '{}'", clip(&w)),
                        });
                    }
                    Tok::Num(x)
                } else if w.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    Tok::Word(w)
                } else {
                    return Err(TokenError {
                        line: l0,
                        col: c0,
                        message: format!(
                            "unexpected text '{}' (expected a directive, a quoted string, a number or a bracket)",
                            clip(&w)
                        ),
                    });
                };
                out.push(Token {
                    tok,
                    line: l0,
                    col: c0,
                });
            }
        }
    }
    Ok(out)
}
