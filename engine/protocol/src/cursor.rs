//! One forward pass over a message's S-expression tokens.
//!
//! The typed percept reader walks the message once, list by list, instead of finding each
//! list's end first and scanning its children again (every byte was read about three times,
//! and reading the percept was the largest stage of a cycle). A reader that is inside a list
//! must leave it through [`Cursor::leave`] or by reading its closing parenthesis, whatever it
//! found there, so one malformed item never shifts the reading of the next. Skipping is a
//! loop over a depth count, never recursion: hostile nesting cannot overflow the stack.

use crate::sexp::SexpError;

/// One token.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Token<'a> {
    /// `(`: a list begins.
    Open,
    /// `)`: the current list ends.
    Close,
    Atom(&'a str),
    /// The text ends.
    End,
}

#[inline]
fn is_separator(b: u8) -> bool {
    // The servers send single spaces, SimSpark accepts tabs and newlines too.
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0)
}

/// A position in a message.
pub struct Cursor<'a> {
    text: &'a str,
    pos: usize,
    /// Where the list being read opened (for the error when it never closes).
    opened_at: usize,
}

impl<'a> Cursor<'a> {
    pub fn new(text: &'a str) -> Self {
        Self {
            text,
            pos: 0,
            opened_at: 0,
        }
    }

    /// Byte offset of the next token's start (after separators).
    pub fn offset(&mut self) -> usize {
        let bytes = self.text.as_bytes();
        while self.pos < bytes.len() && is_separator(bytes[self.pos]) {
            self.pos += 1;
        }
        self.pos
    }

    pub fn next_token(&mut self) -> Token<'a> {
        let at = self.offset();
        let bytes = self.text.as_bytes();
        match bytes.get(at) {
            None => Token::End,
            Some(b'(') => {
                self.pos += 1;
                self.opened_at = at;
                Token::Open
            }
            Some(b')') => {
                self.pos += 1;
                Token::Close
            }
            Some(_) => {
                let len = bytes[at..]
                    .iter()
                    .take_while(|&&b| !is_separator(b) && b != b'(' && b != b')')
                    .count();
                self.pos += len;
                Token::Atom(&self.text[at..at + len])
            }
        }
    }

    /// Read to the end of the list the cursor is in, through its `)`, nested lists and all.
    pub fn leave(&mut self) -> Result<(), SexpError> {
        let opened_at = self.opened_at;
        let mut depth = 1usize;
        loop {
            match self.next_token() {
                Token::Open => depth += 1,
                Token::Close => {
                    depth -= 1;
                    if depth == 0 {
                        return Ok(());
                    }
                }
                Token::Atom(_) => {}
                Token::End => return Err(SexpError::Unclosed(opened_at)),
            }
        }
    }

    /// Inside a list just opened: its head atom, or `None` (the list is then left) when it
    /// is empty or starts with a list.
    pub fn head(&mut self) -> Result<Option<&'a str>, SexpError> {
        self.next_atom()
    }

    /// Inside a list: exactly one more atom, then its end. Anything else: `None`, the list
    /// left.
    pub fn value(&mut self) -> Result<Option<&'a str>, SexpError> {
        match self.next_atom()? {
            Some(value) => self.closes_with(value),
            None => Ok(None),
        }
    }

    /// The next atom of the list; `None` (the list left) when the list ends or a list comes.
    fn next_atom(&mut self) -> Result<Option<&'a str>, SexpError> {
        match self.next_token() {
            Token::Atom(atom) => Ok(Some(atom)),
            Token::Close => Ok(None),
            Token::Open => {
                self.leave()?;
                self.leave()?;
                Ok(None)
            }
            Token::End => Err(SexpError::Unclosed(self.opened_at)),
        }
    }

    /// Inside a list: exactly `N` finite numbers, then its end. Anything else: `None`, the
    /// list left.
    pub fn numbers<const N: usize>(&mut self) -> Result<Option<[f64; N]>, SexpError> {
        let mut out = [0.0; N];
        for slot in &mut out {
            match self.next_token() {
                Token::Atom(atom) => match crate::sexp::parse_finite(atom) {
                    Some(v) => *slot = v,
                    None => return self.leave().map(|()| None),
                },
                Token::Close => return Ok(None),
                Token::Open => {
                    self.leave()?;
                    return self.leave().map(|()| None);
                }
                Token::End => return Err(SexpError::Unclosed(self.opened_at)),
            }
        }
        self.closes_with(out)
    }

    /// `found` if the list ends here; otherwise `None`, the list left.
    fn closes_with<T>(&mut self, found: T) -> Result<Option<T>, SexpError> {
        match self.next_token() {
            Token::Close => Ok(Some(found)),
            Token::End => Err(SexpError::Unclosed(self.opened_at)),
            Token::Open => {
                self.leave()?;
                self.leave().map(|()| None)
            }
            Token::Atom(_) => self.leave().map(|()| None),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_list_is_read_once_and_left_cleanly_whatever_it_holds() {
        let mut c = Cursor::new("(rt 1.5 -2 3)(a 1 nan)(b 1 (x (y)) 2) (c 7)");
        assert_eq!(c.next_token(), Token::Open);
        assert_eq!(c.head().unwrap(), Some("rt"));
        assert_eq!(c.numbers::<3>().unwrap(), Some([1.5, -2.0, 3.0]));
        for name in ["a", "b"] {
            assert_eq!(c.next_token(), Token::Open);
            assert_eq!(c.head().unwrap(), Some(name));
            assert_eq!(c.numbers::<2>().unwrap(), None);
        }
        assert_eq!(c.next_token(), Token::Open);
        assert_eq!(c.head().unwrap(), Some("c"));
        assert_eq!(c.value().unwrap(), Some("7"));
        assert_eq!(c.next_token(), Token::End);
    }

    #[test]
    fn an_unclosed_list_is_an_error_at_its_opening() {
        let mut c = Cursor::new("  (a (b 1 2)");
        assert_eq!(c.next_token(), Token::Open);
        assert_eq!(c.head().unwrap(), Some("a"));
        assert_eq!(c.leave(), Err(SexpError::Unclosed(2)));
        let deep = "(".repeat(100_000);
        let mut c = Cursor::new(&deep);
        assert_eq!(c.next_token(), Token::Open);
        assert!(c.leave().is_err());
    }
}
