//! Tokens of a 6.837 scene file: whitespace-separated words (the course parser reads them with `fscanf("%s")`),
//! with `{` and `}` split off even when written against a word, each with its 1-based line and column for error
//! messages.

/// One word of the file and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub text: String,
    pub line: usize,
    pub col: usize,
}

/// Split `text` into tokens.
pub fn tokenize(text: &str) -> Vec<Token> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut word = String::new();
        let mut start = 0;
        let flush = |word: &mut String, start: usize, out: &mut Vec<Token>| {
            if !word.is_empty() {
                out.push(Token { text: std::mem::take(word), line: i + 1, col: start + 1 });
            }
        };
        for (col, c) in line.chars().enumerate() {
            if c.is_whitespace() {
                flush(&mut word, start, &mut out);
            } else if c == '{' || c == '}' {
                flush(&mut word, start, &mut out);
                out.push(Token { text: c.to_string(), line: i + 1, col: col + 1 });
            } else {
                if word.is_empty() {
                    start = col;
                }
                word.push(c);
            }
        }
        flush(&mut word, start, &mut out);
    }
    out
}
