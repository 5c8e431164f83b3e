//! pbrt's tokens: bare words (directives, `true`/`false`), quoted strings, numbers and brackets, with `#`
//! comments to the end of the line. Every token keeps its file, line and column for errors.

use prism_core::error::token_in_message;
use prism_core::error::{PrismError, Result, SourcePos};
use std::path::Path;

#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    Word(String),
    Str(String),
    Num(f64),
    Open,
    Close,
}

#[derive(Clone, Debug)]
pub struct Token {
    pub tok: Tok,
    pub line: usize,
    pub col: usize,
}

impl Token {
    /// What the token is, for messages.
    pub fn describe(&self) -> String {
        match &self.tok {
            Tok::Word(w) => token_in_message(w),
            Tok::Str(s) => match token_in_message(s) {
                t if t.starts_with('`') => format!("the string \"{s}\""),
                _ => "a quoted string".into(),
            },
            Tok::Num(n) => format!("{n}"),
            Tok::Open => "`[`".into(),
            Tok::Close => "`]`".into(),
        }
    }
}

fn pos(file: &Path, line: usize, col: usize) -> SourcePos {
    SourcePos { file: file.to_path_buf(), line, col }
}

/// Split pbrt text into tokens; an unterminated string or a malformed number is an error at its position.
pub fn tokenize(text: &str, file: &Path) -> Result<Vec<Token>> {
    let mut out = Vec::new();
    let chars: Vec<char> = text.chars().collect();
    let (mut i, mut line, mut col) = (0usize, 1usize, 1usize);
    while i < chars.len() {
        let c = chars[i];
        let (tl, tc) = (line, col);
        let advance = |i: &mut usize, line: &mut usize, col: &mut usize, c: char| {
            *i += 1;
            if c == '\n' {
                *line += 1;
                *col = 1;
            } else {
                *col += 1;
            }
        };
        match c {
            c if c.is_whitespace() => advance(&mut i, &mut line, &mut col, c),
            '#' => {
                while i < chars.len() && chars[i] != '\n' {
                    let d = chars[i];
                    advance(&mut i, &mut line, &mut col, d);
                }
            }
            '[' => {
                out.push(Token { tok: Tok::Open, line: tl, col: tc });
                advance(&mut i, &mut line, &mut col, c);
            }
            ']' => {
                out.push(Token { tok: Tok::Close, line: tl, col: tc });
                advance(&mut i, &mut line, &mut col, c);
            }
            '"' => {
                advance(&mut i, &mut line, &mut col, c);
                let mut s = String::new();
                loop {
                    let Some(&d) = chars.get(i) else {
                        return Err(PrismError::Parse {
                            pos: pos(file, tl, tc),
                            message: "unterminated string".into(),
                        });
                    };
                    if d == '\n' {
                        return Err(PrismError::Parse {
                            pos: pos(file, tl, tc),
                            message: "unterminated string (a newline inside quotes)".into(),
                        });
                    }
                    advance(&mut i, &mut line, &mut col, d);
                    match d {
                        '"' => break,
                        '\\' => {
                            let Some(&e) = chars.get(i) else { continue };
                            advance(&mut i, &mut line, &mut col, e);
                            s.push(match e {
                                'n' => '\n',
                                't' => '\t',
                                other => other,
                            });
                        }
                        _ => s.push(d),
                    }
                }
                out.push(Token { tok: Tok::Str(s), line: tl, col: tc });
            }
            _ => {
                let start = i;
                while i < chars.len() && !chars[i].is_whitespace() && !matches!(chars[i], '[' | ']' | '"' | '#') {
                    let d = chars[i];
                    advance(&mut i, &mut line, &mut col, d);
                }
                let word: String = chars[start..i].iter().collect();
                let first = word.chars().next().unwrap_or(' ');
                let tok = if first.is_ascii_digit() || matches!(first, '-' | '+' | '.') {
                    match word.parse::<f64>() {
                        Ok(v) if v.is_finite() => Tok::Num(v),
                        _ => {
                            return Err(PrismError::Parse {
                                pos: pos(file, tl, tc),
                                message: format!("{} is not a number", token_in_message(&word)),
                            });
                        }
                    }
                } else {
                    Tok::Word(word)
                };
                out.push(Token { tok, line: tl, col: tc });
            }
        }
    }
    Ok(out)
}

/// `n` numbers of a directive's arguments, bare or in brackets.
pub fn nums(tokens: &[Token], i: &mut usize, n: usize, name: &str, pos: &SourcePos) -> Result<Vec<f64>> {
    let bracket = matches!(tokens.get(*i).map(|t| &t.tok), Some(Tok::Open));
    if bracket {
        return bracketed_nums(tokens, i, n, name, pos);
    }
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        match tokens.get(*i) {
            Some(Token { tok: Tok::Num(v), .. }) => {
                out.push(*v);
                *i += 1;
            }
            Some(t) => {
                return Err(PrismError::Parse {
                    pos: SourcePos { line: t.line, col: t.col, ..pos.clone() },
                    message: format!("{name} expects {n} numbers, got {} after {}", t.describe(), out.len()),
                });
            }
            None => {
                return Err(PrismError::Parse {
                    pos: pos.clone(),
                    message: format!("{name} expects {n} numbers, the file ends after {}", out.len()),
                });
            }
        }
    }
    Ok(out)
}

/// `n` numbers in brackets (or bare).
pub fn bracketed_nums(tokens: &[Token], i: &mut usize, n: usize, name: &str, pos: &SourcePos) -> Result<Vec<f64>> {
    if !matches!(tokens.get(*i).map(|t| &t.tok), Some(Tok::Open)) {
        return nums(tokens, i, n, name, pos);
    }
    *i += 1;
    let v = nums(tokens, i, n, name, pos)?;
    match tokens.get(*i) {
        Some(Token { tok: Tok::Close, .. }) => {
            *i += 1;
            Ok(v)
        }
        Some(t) => Err(PrismError::Parse {
            pos: SourcePos { line: t.line, col: t.col, ..pos.clone() },
            message: format!("{name} expects {n} numbers in brackets, got {} more", t.describe()),
        }),
        None => Err(PrismError::Parse { pos: pos.clone(), message: format!("{name}: missing `]`") }),
    }
}

/// One quoted string argument.
pub fn string(tokens: &[Token], i: &mut usize, name: &str, pos: &SourcePos) -> Result<String> {
    match tokens.get(*i) {
        Some(Token { tok: Tok::Str(s), .. }) => {
            *i += 1;
            Ok(s.clone())
        }
        Some(t) => Err(PrismError::Parse {
            pos: SourcePos { line: t.line, col: t.col, ..pos.clone() },
            message: format!("{name} expects a quoted string, got {}", t.describe()),
        }),
        None => Err(PrismError::Parse { pos: pos.clone(), message: format!("{name} expects a quoted string") }),
    }
}
