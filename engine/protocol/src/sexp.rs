//! A borrowing S-expression reader for server messages.
//!
//! Nothing is allocated: a [`List`] is a view of the text between its parentheses, and its
//! children are found by scanning when iterated. Every list handed out has been checked to be
//! balanced, so iterating it can never fail; only the top-level reader reports errors. The
//! reader never recurses, so hostile nesting depth cannot overflow the stack.

use std::fmt;

/// One expression: an atom or a parenthesised list.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sexp<'a> {
    Atom(&'a str),
    List(List<'a>),
}

impl<'a> Sexp<'a> {
    pub fn as_atom(&self) -> Option<&'a str> {
        match self {
            Sexp::Atom(a) => Some(a),
            Sexp::List(_) => None,
        }
    }

    pub fn as_list(&self) -> Option<List<'a>> {
        match self {
            Sexp::List(l) => Some(*l),
            Sexp::Atom(_) => None,
        }
    }

    /// The atom read as a finite number.
    pub fn as_f64(&self) -> Option<f64> {
        self.as_atom().and_then(parse_finite)
    }
}

/// A finite `f64` from an atom; `nan`, `inf` and anything malformed give `None`.
pub fn parse_finite(atom: &str) -> Option<f64> {
    plain_decimal(atom).or_else(|| atom.parse::<f64>().ok().filter(|v| v.is_finite()))
}

/// The servers' numbers are short plain decimals (`-0.35`, `12.5`, `3`): read as an integer
/// and one division by a power of ten, which is exact when both are below 2^53 and 10^22
/// (Clinger's fast path), so the result is the correctly rounded value `str::parse` gives.
/// Anything else (exponents, long digit strings, odd forms) is left to `str::parse`.
fn plain_decimal(atom: &str) -> Option<f64> {
    const POWERS: [f64; 16] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
    ];
    let bytes = atom.as_bytes();
    let (negative, digits) = match bytes.first()? {
        b'-' => (true, &bytes[1..]),
        b'+' => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    let (mut mantissa, mut count, mut decimals, mut seen_point) = (0u64, 0usize, 0usize, false);
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                mantissa = mantissa * 10 + u64::from(b - b'0');
                count += 1;
                decimals += usize::from(seen_point);
            }
            b'.' if !seen_point => seen_point = true,
            _ => return None,
        }
        if count > 15 {
            return None;
        }
    }
    if count == 0 {
        return None;
    }
    let value = mantissa as f64 / POWERS[decimals];
    Some(if negative { -value } else { value })
}

/// A balanced list; `inner` is the text between its parentheses.
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct List<'a> {
    inner: &'a str,
}

impl fmt::Debug for List<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({})", self.inner)
    }
}

impl<'a> List<'a> {
    /// The children in order.
    pub fn iter(&self) -> Children<'a> {
        Children {
            rest: self.inner.as_bytes(),
            text: self.inner,
            pos: 0,
        }
    }

    /// The first child if it is an atom (the "name" of a predicate).
    pub fn head(&self) -> Option<&'a str> {
        self.iter().next().and_then(|s| s.as_atom())
    }

    /// The children after the head.
    pub fn tail(&self) -> std::iter::Skip<Children<'a>> {
        self.iter().skip(1)
    }

    /// The first child list whose head is `name`, e.g. `(n torso)` in `(GYR (n torso) (rt 1 2 3))`.
    pub fn child(&self, name: &str) -> Option<List<'a>> {
        self.iter()
            .filter_map(|c| c.as_list())
            .find(|l| l.head() == Some(name))
    }

    /// The single atom after `name` in the child list `(name value)`.
    pub fn value(&self, name: &str) -> Option<&'a str> {
        self.child(name)?.tail().next()?.as_atom()
    }

    /// `N` finite numbers after `name` in the child list `(name v1 … vN)`.
    pub fn numbers<const N: usize>(&self, name: &str) -> Option<[f64; N]> {
        self.child(name)?.tail_numbers()
    }

    /// Exactly `N` finite numbers after the head.
    pub fn tail_numbers<const N: usize>(&self) -> Option<[f64; N]> {
        let mut out = [0.0; N];
        let mut it = self.tail();
        for slot in &mut out {
            *slot = it.next()?.as_f64()?;
        }
        it.next().is_none().then_some(out)
    }

    /// The raw text between the parentheses.
    pub fn as_str(&self) -> &'a str {
        self.inner
    }
}

/// Iterator over a list's children. Only constructed over balanced text.
pub struct Children<'a> {
    text: &'a str,
    rest: &'a [u8],
    pos: usize,
}

impl<'a> Iterator for Children<'a> {
    type Item = Sexp<'a>;

    fn next(&mut self) -> Option<Sexp<'a>> {
        let (item, consumed) = read_one(self.text, self.rest, self.pos).ok()??;
        self.rest = &self.rest[consumed - self.pos..];
        self.pos = consumed;
        Some(item)
    }
}

/// A malformed message.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SexpError {
    #[error("unbalanced `(` opened at byte {0}")]
    Unclosed(usize),
    #[error("unexpected `)` at byte {0}")]
    UnexpectedClose(usize),
}

/// Iterator over the top-level expressions of a message. Stops after the first error.
pub struct TopLevel<'a> {
    text: &'a str,
    pos: usize,
    failed: bool,
}

/// Read the top-level expressions of `text`.
pub fn top_level(text: &str) -> TopLevel<'_> {
    TopLevel {
        text,
        pos: 0,
        failed: false,
    }
}

impl<'a> Iterator for TopLevel<'a> {
    type Item = Result<Sexp<'a>, SexpError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        let rest = &self.text.as_bytes()[self.pos..];
        match read_one(self.text, rest, self.pos) {
            Ok(Some((item, end))) => {
                self.pos = end;
                Some(Ok(item))
            }
            Ok(None) => None,
            Err(e) => {
                self.failed = true;
                Some(Err(e))
            }
        }
    }
}

#[inline]
fn is_separator(b: u8) -> bool {
    // The servers send single spaces, SimSpark accepts tabs and newlines too; be liberal in
    // what we read.
    matches!(b, b' ' | b'\t' | b'\n' | b'\r' | 0)
}

/// Read one expression from `rest` (which starts at byte `start` of `text`).
/// Returns the expression and the byte offset just after it, or `None` at the end.
fn read_one<'a>(
    text: &'a str,
    rest: &[u8],
    start: usize,
) -> Result<Option<(Sexp<'a>, usize)>, SexpError> {
    let skip = rest.iter().take_while(|&&b| is_separator(b)).count();
    let begin = start + skip;
    let rest = &rest[skip..];
    match rest.first() {
        None => Ok(None),
        Some(b'(') => {
            let mut depth = 0usize;
            for (i, &b) in rest.iter().enumerate() {
                match b {
                    b'(' => depth += 1,
                    b')' => {
                        depth -= 1;
                        if depth == 0 {
                            let inner = &text[begin + 1..begin + i];
                            return Ok(Some((Sexp::List(List { inner }), begin + i + 1)));
                        }
                    }
                    _ => {}
                }
            }
            Err(SexpError::Unclosed(begin))
        }
        Some(b')') => Err(SexpError::UnexpectedClose(begin)),
        Some(_) => {
            let len = rest
                .iter()
                .take_while(|&&b| !is_separator(b) && b != b'(' && b != b')')
                .count();
            Ok(Some((Sexp::Atom(&text[begin..begin + len]), begin + len)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn first_list(text: &str) -> List<'_> {
        top_level(text).next().unwrap().unwrap().as_list().unwrap()
    }

    #[test]
    fn reads_both_servers_spacing() {
        for text in [
            "(GYR (n torso) (rt 1.5 -2 3))",
            "(GYR(n torso)(rt 1.5 -2 3))",
            "(GYR\t(n torso)\n(rt 1.5 -2 3) )",
        ] {
            let l = first_list(text);
            assert_eq!(l.head(), Some("GYR"));
            assert_eq!(l.value("n"), Some("torso"));
            assert_eq!(l.numbers::<3>("rt"), Some([1.5, -2.0, 3.0]));
        }
    }

    #[test]
    fn top_level_sequence_and_empty_list() {
        let items: Vec<_> = top_level("(time (now 1.0))(See )(syn)")
            .map(|r| r.unwrap())
            .collect();
        assert_eq!(items.len(), 3);
        assert_eq!(items[1].as_list().unwrap().head(), Some("See"));
        assert_eq!(items[1].as_list().unwrap().tail().count(), 0);
        let empty = first_list("()");
        assert_eq!(empty.head(), None);
    }

    #[test]
    fn malformed_input_is_an_error_not_a_panic() {
        let r: Vec<_> = top_level("(a (b)").collect();
        assert_eq!(r, vec![Err(SexpError::Unclosed(0))]);
        let r: Vec<_> = top_level("(a) ) (b)").collect();
        assert_eq!(r.len(), 2);
        assert_eq!(r[1], Err(SexpError::UnexpectedClose(4)));
    }

    #[test]
    fn numbers_must_be_finite_and_exactly_n() {
        let l = first_list("(x (a 1 nan) (b 1 2 3) (c 1 2))");
        assert_eq!(l.numbers::<2>("a"), None);
        assert_eq!(l.numbers::<2>("b"), None);
        assert_eq!(l.numbers::<2>("c"), Some([1.0, 2.0]));
    }

    #[test]
    fn plain_decimals_read_exactly_as_the_standard_parser_does() {
        for text in [
            "0",
            "-0.35",
            "12.5",
            "3.",
            ".5",
            "-.25",
            "+7.125",
            "0.1",
            "123456789012345",
            "0.000000000000001",
            "9.99",
            "-273.15",
            "1e3",
            "1.5E-2",
            "12345678901234567",
        ] {
            assert_eq!(parse_finite(text), text.parse::<f64>().ok(), "{text}");
        }
        for bad in ["", "-", ".", "1.2.3", "1-2", "nan", "inf", "0x10", "1,5"] {
            assert_eq!(parse_finite(bad), None, "{bad}");
        }
        // -0 keeps its sign, as `str::parse` gives it.
        assert!(parse_finite("-0.0").unwrap().is_sign_negative());
    }

    proptest::proptest! {
        #[test]
        fn any_short_decimal_matches_the_standard_parser(
            int in 0u64..10_000_000, frac in 0u64..1_000_000, places in 0usize..7, negative: bool
        ) {
            let text = format!(
                "{}{int}.{:0>places$}",
                if negative { "-" } else { "" },
                frac % 10u64.pow(places as u32)
            );
            proptest::prop_assert_eq!(parse_finite(&text), text.parse::<f64>().ok());
        }
    }

    #[test]
    fn deep_nesting_does_not_overflow() {
        let text = format!("{}{}", "(".repeat(200_000), ")".repeat(200_000));
        let l = first_list(&text);
        assert!(l.iter().next().is_some());
    }
}
