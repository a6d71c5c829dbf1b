//! A reader for the subset of RON that behavior and strategy files use, keeping a byte span
//! for every value so that semantic errors (unknown node, bad type, value out of range) can
//! point at the exact place in the file, which a plain serde deserializer cannot do.

use std::fmt;

/// A byte range in a source file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct Span {
    pub start: usize,
    pub end: usize,
}

impl Span {
    pub fn new(start: usize, end: usize) -> Self {
        Self { start, end }
    }
}

#[derive(Debug, Clone)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct Field {
    pub name: Ident,
    pub value: Node,
}

/// The contents of a parenthesised group: named fields `(a: 1)` or positional items `(1, 2)`.
#[derive(Debug, Clone)]
pub enum Body {
    Fields(Vec<Field>),
    Items(Vec<Node>),
}

#[derive(Debug, Clone)]
pub enum NodeKind {
    /// `Name(...)` or `(...)`.
    Struct {
        name: Option<Ident>,
        body: Body,
    },
    /// A bare identifier such as `None` or an enum variant.
    Unit(Ident),
    List(Vec<Node>),
    Map(Vec<(Node, Node)>),
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
}

#[derive(Debug, Clone)]
pub struct Node {
    pub kind: NodeKind,
    pub span: Span,
}

impl Node {
    /// What the value looks like, for "expected X, found Y" messages.
    pub fn describe(&self) -> String {
        match &self.kind {
            NodeKind::Struct { name: Some(n), .. } => format!("`{}(...)`", n.name),
            NodeKind::Struct { name: None, .. } => "a tuple".into(),
            NodeKind::Unit(id) => format!("`{}`", id.name),
            NodeKind::List(_) => "a list".into(),
            NodeKind::Map(_) => "a map".into(),
            NodeKind::Str(_) => "a string".into(),
            NodeKind::Int(_) => "an integer".into(),
            NodeKind::Float(_) => "a float".into(),
            NodeKind::Bool(_) => "a boolean".into(),
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct SyntaxError {
    pub span: Span,
    pub message: String,
    pub hint: Option<String>,
}

impl fmt::Display for SyntaxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

/// Nesting deeper than this is rejected rather than risking a stack overflow on hostile input.
const MAX_DEPTH: usize = 128;

pub fn parse(text: &str) -> Result<Node, SyntaxError> {
    let mut reader = Reader {
        text,
        bytes: text.as_bytes(),
        pos: 0,
        depth: 0,
    };
    reader.skip_trivia()?;
    reader.skip_attributes()?;
    let node = reader.value()?;
    reader.skip_trivia()?;
    if reader.pos < reader.bytes.len() {
        return Err(reader.error_here("unexpected text after the end of the value", None));
    }
    Ok(node)
}

struct Reader<'a> {
    text: &'a str,
    bytes: &'a [u8],
    pos: usize,
    depth: usize,
}

impl Reader<'_> {
    fn error_here(&self, message: &str, hint: Option<&str>) -> SyntaxError {
        let len = self.text[self.pos..]
            .chars()
            .next()
            .map_or(0, char::len_utf8);
        SyntaxError {
            span: Span::new(self.pos, self.pos + len),
            message: message.to_string(),
            hint: hint.map(str::to_string),
        }
    }

    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.pos).copied()
    }

    fn skip_trivia(&mut self) -> Result<(), SyntaxError> {
        loop {
            match self.peek() {
                Some(b' ' | b'\t' | b'\n' | b'\r') => self.pos += 1,
                Some(b'/') if self.bytes.get(self.pos + 1) == Some(&b'/') => {
                    while self.peek().is_some_and(|b| b != b'\n') {
                        self.pos += 1;
                    }
                }
                Some(b'/') if self.bytes.get(self.pos + 1) == Some(&b'*') => {
                    self.block_comment()?
                }
                _ => return Ok(()),
            }
        }
    }

    fn block_comment(&mut self) -> Result<(), SyntaxError> {
        let start = self.pos;
        let mut nesting = 0usize;
        while self.pos < self.bytes.len() {
            if self.bytes[self.pos..].starts_with(b"/*") {
                nesting += 1;
                self.pos += 2;
            } else if self.bytes[self.pos..].starts_with(b"*/") {
                nesting -= 1;
                self.pos += 2;
                if nesting == 0 {
                    return Ok(());
                }
            } else {
                self.pos += 1;
            }
        }
        Err(SyntaxError {
            span: Span::new(start, start + 2),
            message: "unterminated block comment".into(),
            hint: Some("close it with `*/`".into()),
        })
    }

    /// RON files may start with `#![enable(...)]`; those switches do not change this subset.
    fn skip_attributes(&mut self) -> Result<(), SyntaxError> {
        while self.bytes[self.pos..].starts_with(b"#!") {
            match self.text[self.pos..].find(']') {
                Some(end) => self.pos += end + 1,
                None => return Err(self.error_here("unterminated attribute", None)),
            }
            self.skip_trivia()?;
        }
        Ok(())
    }

    fn expect(&mut self, byte: u8, what: &str) -> Result<(), SyntaxError> {
        self.skip_trivia()?;
        if self.peek() == Some(byte) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.unexpected(what))
        }
    }

    fn unexpected(&self, expected: &str) -> SyntaxError {
        if self.pos >= self.bytes.len() {
            let message = format!("unexpected end of file, expected {expected}");
            let mut error = self.error_here(&message, Some("a bracket may be left open"));
            error.span = Span::new(self.pos.saturating_sub(1), self.pos);
            return error;
        }
        let found = self.text[self.pos..].chars().next().unwrap_or(' ');
        self.error_here(&format!("expected {expected}, found `{found}`"), None)
    }

    fn value(&mut self) -> Result<Node, SyntaxError> {
        self.skip_trivia()?;
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.error_here("values are nested too deeply", None));
        }
        let start = self.pos;
        let kind = match self.peek() {
            Some(b'(') => NodeKind::Struct {
                name: None,
                body: self.group()?,
            },
            Some(b'[') => NodeKind::List(self.list()?),
            Some(b'{') => NodeKind::Map(self.map()?),
            Some(b'"') => NodeKind::Str(self.string()?),
            Some(b'-' | b'+' | b'.' | b'0'..=b'9') => self.number()?,
            Some(b) if b.is_ascii_alphabetic() || b == b'_' => {
                let ident = self.ident()?;
                let after_name = self.pos;
                self.skip_trivia()?;
                match ident.name.as_str() {
                    "true" => NodeKind::Bool(true),
                    "false" => NodeKind::Bool(false),
                    "inf" => NodeKind::Float(f64::INFINITY),
                    _ if self.peek() == Some(b'(') => NodeKind::Struct {
                        name: Some(ident),
                        body: self.group()?,
                    },
                    _ => {
                        self.pos = after_name;
                        NodeKind::Unit(ident)
                    }
                }
            }
            _ => return Err(self.unexpected("a value")),
        };
        self.depth -= 1;
        Ok(Node {
            kind,
            span: Span::new(start, self.pos),
        })
    }

    fn ident(&mut self) -> Result<Ident, SyntaxError> {
        self.skip_trivia()?;
        let start = self.pos;
        while self
            .peek()
            .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_')
        {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.unexpected("a name"));
        }
        Ok(Ident {
            name: self.text[start..self.pos].to_string(),
            span: Span::new(start, self.pos),
        })
    }

    /// Whether the next tokens are `name:` (a field) rather than a value.
    fn at_field(&mut self) -> Result<bool, SyntaxError> {
        self.skip_trivia()?;
        let saved = self.pos;
        let is_field = if self
            .peek()
            .is_some_and(|b| b.is_ascii_alphabetic() || b == b'_')
        {
            self.ident()?;
            self.skip_trivia()?;
            self.peek() == Some(b':')
        } else {
            false
        };
        self.pos = saved;
        Ok(is_field)
    }

    fn group(&mut self) -> Result<Body, SyntaxError> {
        self.expect(b'(', "`(`")?;
        self.skip_trivia()?;
        if self.at_field()? {
            let mut fields = Vec::new();
            self.separated(b')', |reader| {
                let name = reader.ident()?;
                reader.expect(b':', "`:` after a field name")?;
                fields.push(Field {
                    name,
                    value: reader.value()?,
                });
                Ok(())
            })?;
            Ok(Body::Fields(fields))
        } else {
            let mut items = Vec::new();
            self.separated(b')', |reader| {
                items.push(reader.value()?);
                Ok(())
            })?;
            Ok(Body::Items(items))
        }
    }

    fn list(&mut self) -> Result<Vec<Node>, SyntaxError> {
        self.expect(b'[', "`[`")?;
        let mut items = Vec::new();
        self.separated(b']', |reader| {
            items.push(reader.value()?);
            Ok(())
        })?;
        Ok(items)
    }

    fn map(&mut self) -> Result<Vec<(Node, Node)>, SyntaxError> {
        self.expect(b'{', "`{`")?;
        let mut entries = Vec::new();
        self.separated(b'}', |reader| {
            let key = reader.value()?;
            reader.expect(b':', "`:` after a map key")?;
            entries.push((key, reader.value()?));
            Ok(())
        })?;
        Ok(entries)
    }

    /// Parses comma-separated elements up to `close`, allowing a trailing comma.
    fn separated(
        &mut self,
        close: u8,
        mut element: impl FnMut(&mut Self) -> Result<(), SyntaxError>,
    ) -> Result<(), SyntaxError> {
        let closing = format!("`,` or `{}`", close as char);
        loop {
            self.skip_trivia()?;
            if self.peek() == Some(close) {
                self.pos += 1;
                return Ok(());
            }
            element(self)?;
            self.skip_trivia()?;
            match self.peek() {
                Some(b',') => self.pos += 1,
                Some(b) if b == close => {}
                _ => {
                    let mut error = self.unexpected(&closing);
                    if self.pos < self.bytes.len() {
                        error.hint = Some("is a comma missing?".into());
                    }
                    return Err(error);
                }
            }
        }
    }

    fn string(&mut self) -> Result<String, SyntaxError> {
        let start = self.pos;
        self.pos += 1;
        let mut out = String::new();
        loop {
            let Some(c) = self.text[self.pos..].chars().next() else {
                return Err(SyntaxError {
                    span: Span::new(start, start + 1),
                    message: "unterminated string".into(),
                    hint: Some("close it with `\"`".into()),
                });
            };
            self.pos += c.len_utf8();
            match c {
                '"' => return Ok(out),
                '\\' => out.push(self.escape()?),
                c => out.push(c),
            }
        }
    }

    fn escape(&mut self) -> Result<char, SyntaxError> {
        let c = self.peek().ok_or_else(|| self.unexpected("an escape"))?;
        self.pos += 1;
        Ok(match c {
            b'n' => '\n',
            b't' => '\t',
            b'r' => '\r',
            b'0' => '\0',
            b'\\' => '\\',
            b'"' => '"',
            b'\'' => '\'',
            b'u' if self.peek() == Some(b'{') => {
                let close = self.text[self.pos..].find('}');
                let code = close
                    .and_then(|end| {
                        u32::from_str_radix(&self.text[self.pos + 1..self.pos + end], 16).ok()
                    })
                    .and_then(char::from_u32);
                match (close, code) {
                    (Some(end), Some(ch)) => {
                        self.pos += end + 1;
                        ch
                    }
                    _ => return Err(self.error_here("invalid unicode escape", None)),
                }
            }
            _ => {
                self.pos -= 1;
                return Err(self.error_here(
                    "unknown escape sequence",
                    Some("use `\\\\` for a backslash"),
                ));
            }
        })
    }

    fn number(&mut self) -> Result<NodeKind, SyntaxError> {
        let start = self.pos;
        if matches!(self.peek(), Some(b'-' | b'+')) {
            self.pos += 1;
        }
        if self.bytes[self.pos..].starts_with(b"inf") {
            self.pos += 3;
            let negative = self.bytes[start] == b'-';
            return Ok(NodeKind::Float(if negative {
                f64::NEG_INFINITY
            } else {
                f64::INFINITY
            }));
        }
        let mut is_float = false;
        while let Some(b) = self.peek() {
            match b {
                b'0'..=b'9' | b'_' => {}
                b'.' | b'e' | b'E' => is_float = true,
                b'-' | b'+' if matches!(self.bytes[self.pos - 1], b'e' | b'E') => {}
                _ => break,
            }
            self.pos += 1;
        }
        let literal: String = self.text[start..self.pos]
            .chars()
            .filter(|&c| c != '_')
            .collect();
        let span = Span::new(start, self.pos);
        let bad = |what: &str| SyntaxError {
            span,
            message: format!("invalid {what} `{literal}`"),
            hint: None,
        };
        if is_float {
            literal
                .parse()
                .map(NodeKind::Float)
                .map_err(|_| bad("number"))
        } else {
            literal
                .parse()
                .map(NodeKind::Int)
                .map_err(|_| bad("integer"))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_point_at_values() {
        let text = "Action(name: \"WalkTo\", speed: 0.5, to: (1, -2.5e0))";
        let node = parse(text).unwrap();
        let NodeKind::Struct {
            name: Some(name),
            body: Body::Fields(fields),
        } = node.kind
        else {
            panic!("expected a struct");
        };
        assert_eq!(name.name, "Action");
        assert_eq!(
            &text[fields[0].value.span.start..fields[0].value.span.end],
            "\"WalkTo\""
        );
        assert!(matches!(fields[1].value.kind, NodeKind::Float(x) if x == 0.5));
        assert_eq!(
            &text[fields[2].value.span.start..fields[2].value.span.end],
            "(1, -2.5e0)"
        );
    }

    #[test]
    fn comments_maps_lists_and_trailing_commas() {
        let text = "/* a /* nested */ comment */ { \"a\": [1, 2,], // line\n \"b\": None, }";
        let NodeKind::Map(entries) = parse(text).unwrap().kind else {
            panic!("expected a map")
        };
        assert_eq!(entries.len(), 2);
        assert!(matches!(&entries[1].1.kind, NodeKind::Unit(id) if id.name == "None"));
    }

    #[test]
    fn errors_are_located() {
        let error = parse("Sequence([Action(name: \"A\") Action(name: \"B\")])").unwrap_err();
        assert_eq!(error.span.start, 28);
        assert_eq!(error.hint.as_deref(), Some("is a comma missing?"));
        let error = parse("Sequence([").unwrap_err();
        assert!(error.message.contains("end of file"), "{}", error.message);
        assert!(parse("\"abc")
            .unwrap_err()
            .message
            .contains("unterminated string"));
    }

    #[test]
    fn hostile_input_does_not_panic() {
        let deep = "[".repeat(10_000);
        assert!(parse(&deep).is_err());
        for text in [
            "",
            "(",
            "-",
            "1e",
            "\"\\u{zz}\"",
            "a(b:",
            "/*",
            "#!",
            "é",
            "\"\\",
            "{1:}",
        ] {
            assert!(parse(text).is_err(), "{text:?} should be rejected");
        }
    }
}
