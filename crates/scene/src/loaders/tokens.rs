//! Whitespace-separated tokens from a byte stream, with the line number, for the text forms
//! of PLY and STL. Tokens and lines are bounded in length, so a stream without separators
//! cannot grow a buffer without limit; `\r` counts as whitespace (CRLF files).
use std::io::BufRead;

/// Longest token accepted (a number or keyword; names are skipped with [`Tokens::skip_line`]).
const MAX_TOKEN: usize = 256;

pub(crate) struct Tokens<R> {
    r: R,
    /// 1-based line of the last token returned.
    pub(crate) line: usize,
    next_line: usize,
    tok: Vec<u8>,
}

impl<R: BufRead> Tokens<R> {
    pub(crate) fn new(r: R, first_line: usize) -> Self {
        Tokens {
            r,
            line: first_line,
            next_line: first_line,
            tok: Vec::new(),
        }
    }

    /// The next token, `Ok(None)` at the end of the stream.
    pub(crate) fn token(&mut self) -> Result<Option<&[u8]>, String> {
        self.tok.clear();
        loop {
            let buf = self.r.fill_buf().map_err(|e| e.to_string())?;
            if buf.is_empty() {
                break;
            }
            let mut used = 0;
            let mut done = false;
            for &b in buf {
                if b.is_ascii_whitespace() {
                    if !self.tok.is_empty() {
                        done = true;
                        break;
                    }
                    if b == b'\n' {
                        self.next_line += 1;
                    }
                } else {
                    if self.tok.is_empty() {
                        self.line = self.next_line;
                    }
                    if self.tok.len() >= MAX_TOKEN {
                        return Err(format!("a word of more than {MAX_TOKEN} characters"));
                    }
                    self.tok.push(b);
                }
                used += 1;
            }
            self.r.consume(used);
            if done {
                break;
            }
        }
        Ok((!self.tok.is_empty()).then_some(&self.tok[..]))
    }

    /// The next token as a number; `what` names it in the error (the caller adds
    /// [`Tokens::line`]).
    pub(crate) fn number(&mut self, what: &str) -> Result<f64, String> {
        match self.token()? {
            Some(t) => std::str::from_utf8(t)
                .ok()
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| format!("{what}: {:?} is not a number", String::from_utf8_lossy(t))),
            None => Err(format!("{what}: the file ends here")),
        }
    }

    /// Skips the rest of the current line (a name after `solid`).
    pub(crate) fn skip_line(&mut self) -> Result<(), String> {
        loop {
            let buf = self.r.fill_buf().map_err(|e| e.to_string())?;
            if buf.is_empty() {
                return Ok(());
            }
            if let Some(i) = buf.iter().position(|&b| b == b'\n') {
                self.r.consume(i + 1);
                self.next_line += 1;
                return Ok(());
            }
            let n = buf.len();
            self.r.consume(n);
        }
    }
}

impl<R> Tokens<R> {
    /// The stream itself, for binary data after a text header.
    pub(crate) fn reader(&mut self) -> &mut R {
        &mut self.r
    }
}
