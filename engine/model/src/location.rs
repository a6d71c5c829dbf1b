//! Source locations for errors found in data files.

use std::fmt;

/// A 1-based line and column in a data file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SourceLocation {
    pub line: usize,
    pub column: usize,
}

impl SourceLocation {
    /// The location of byte `offset` in `text` (clamped to the end of the text).
    pub fn from_offset(text: &str, offset: usize) -> Self {
        let offset = offset.min(text.len());
        let before = &text[..floor_char_boundary(text, offset)];
        let line = before.bytes().filter(|&b| b == b'\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before[line_start..].chars().count() + 1;
        Self { line, column }
    }

    /// The location of the first occurrence of `needle` in `text`, if any.
    pub fn of_first(text: &str, needle: &str) -> Option<Self> {
        text.find(needle).map(|i| Self::from_offset(text, i))
    }
}

fn floor_char_boundary(text: &str, mut i: usize) -> usize {
    while i > 0 && !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

impl fmt::Display for SourceLocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// The longest error message kept whole: the parser's messages quote names from the input.
const MAX_MESSAGE_CHARS: usize = 200;

/// Deserialize RON text; a syntax or type error comes back located in `file`. A leading
/// byte-order mark (written by some editors, invisible in them) is not part of the value.
pub fn parse_ron<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T, Located> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    ron::from_str(text).map_err(|e| {
        let mut message = e.code.to_string();
        if message.chars().count() > MAX_MESSAGE_CHARS {
            message = message.chars().take(MAX_MESSAGE_CHARS).collect();
            message.push('…');
        }
        Located {
            file: file.to_string(),
            at: SourceLocation {
                line: e.position.line,
                column: e.position.col,
            },
            message,
        }
    })
}

/// A message tied to a place in a file.
#[derive(Debug, Clone, PartialEq)]
pub struct Located {
    pub file: String,
    pub at: SourceLocation,
    pub message: String,
}

impl fmt::Display for Located {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.at, self.message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_byte_order_mark_is_skipped_and_long_names_are_cut() {
        let value: (u32, u32) = parse_ron("x", "\u{feff}(1, 2)").unwrap();
        assert_eq!(value, (1, 2));
        #[derive(Debug, serde::Deserialize)]
        enum Side {
            Left,
        }
        let error = parse_ron::<Side>("x", &"K".repeat(100_000)).unwrap_err();
        assert!(error.message.contains("KKK"), "{error}");
        assert!(error.to_string().len() < 300, "{error}");
        assert!(matches!(parse_ron::<Side>("x", "Left"), Ok(Side::Left)));
    }

    #[test]
    fn offsets_map_to_lines_and_columns() {
        let text = "ab\ncd\n";
        assert_eq!(
            SourceLocation::from_offset(text, 0),
            SourceLocation { line: 1, column: 1 }
        );
        assert_eq!(
            SourceLocation::from_offset(text, 4),
            SourceLocation { line: 2, column: 2 }
        );
        assert_eq!(
            SourceLocation::from_offset(text, 99),
            SourceLocation { line: 3, column: 1 }
        );
    }
}
