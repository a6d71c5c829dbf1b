//! Located diagnostics: every problem in every file, rendered like rustc or as JSON for CI.

use crate::syntax::Span;
use serde::Serialize;
use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
}

/// One loaded file's text, kept so diagnostics can show an excerpt.
#[derive(Debug)]
pub struct SourceFile {
    pub path: PathBuf,
    pub text: String,
    line_starts: Vec<usize>,
}

impl SourceFile {
    /// A leading byte-order mark is dropped: editors hide it, so positions count without it.
    pub fn new(path: PathBuf, text: String) -> Self {
        let text = crate::files::strip_bom_owned(text);
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Self {
            path,
            text,
            line_starts,
        }
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let line = self.line_starts.partition_point(|&start| start <= offset) - 1;
        let start = self.line_starts[line];
        let column = self
            .text
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count());
        (line + 1, column + 1)
    }

    fn line_text(&self, line: usize) -> &str {
        let start = self.line_starts[line - 1];
        let end = self
            .line_starts
            .get(line)
            .map_or(self.text.len(), |&next| next - 1);
        self.text
            .get(start..end)
            .unwrap_or("")
            .trim_end_matches('\r')
    }
}

/// Where a diagnostic points: a file and a byte span in it.
#[derive(Debug, Clone)]
pub struct Location {
    pub file: Arc<SourceFile>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct Diagnostic {
    pub severity: Severity,
    /// A stable kebab-case name of the error class, e.g. `unknown-node`.
    pub code: &'static str,
    pub message: String,
    pub location: Option<Location>,
    pub hint: Option<String>,
}

impl Diagnostic {
    /// The message is kept to a bounded length (see [`bounded`]): it may quote the input.
    pub fn error(code: &'static str, message: impl Into<String>) -> Self {
        let message = message.into();
        let message = match bounded(&message) {
            Cow::Borrowed(_) => message,
            Cow::Owned(shortened) => shortened,
        };
        Self {
            severity: Severity::Error,
            code,
            message,
            location: None,
            hint: None,
        }
    }

    pub fn warning(code: &'static str, message: impl Into<String>) -> Self {
        Self {
            severity: Severity::Warning,
            ..Self::error(code, message)
        }
    }

    pub fn at(mut self, file: &Arc<SourceFile>, span: Span) -> Self {
        self.location = Some(Location {
            file: file.clone(),
            span,
        });
        self
    }

    pub fn hint(mut self, hint: impl Into<String>) -> Self {
        self.hint = Some(hint.into());
        self
    }

    pub fn maybe_hint(mut self, hint: Option<String>) -> Self {
        self.hint = hint;
        self
    }
}

/// The result of validating a set of files.
#[derive(Debug, Clone, Default)]
pub struct Report {
    pub diagnostics: Vec<Diagnostic>,
}

#[derive(Serialize)]
struct JsonDiagnostic<'a> {
    severity: Severity,
    code: &'a str,
    message: Cow<'a, str>,
    file: Option<String>,
    line: Option<usize>,
    column: Option<usize>,
    end_line: Option<usize>,
    end_column: Option<usize>,
    hint: Option<Cow<'a, str>>,
}

impl Report {
    pub fn push(&mut self, diagnostic: Diagnostic) {
        self.diagnostics.push(diagnostic);
    }

    pub fn extend(&mut self, other: Report) {
        self.diagnostics.extend(other.diagnostics);
    }

    pub fn error_count(&self) -> usize {
        self.diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Error)
            .count()
    }

    pub fn warning_count(&self) -> usize {
        self.diagnostics
            .iter()
            .filter(|d| d.severity == Severity::Warning)
            .count()
    }

    pub fn has_errors(&self) -> bool {
        self.error_count() > 0
    }

    /// Orders diagnostics by file, then position, so output is stable across runs.
    pub fn sort(&mut self) {
        self.diagnostics.sort_by(|a, b| {
            let key = |d: &Diagnostic| {
                d.location
                    .as_ref()
                    .map(|l| (l.file.path.clone(), l.span.start, l.span.end))
            };
            key(a)
                .cmp(&key(b))
                .then(a.severity.cmp(&b.severity))
                .then(a.message.cmp(&b.message))
        });
    }

    /// rustc-style text with a caret excerpt, paths shown as given.
    pub fn render_text(&self) -> String {
        self.render_text_relative(Path::new(""))
    }

    /// Like [`Report::render_text`] with paths shown relative to `base` (for stable snapshots).
    pub fn render_text_relative(&self, base: &Path) -> String {
        let mut out = String::new();
        let prefix = format!("{}/", base.display());
        for diagnostic in &self.diagnostics {
            let mut diagnostic = diagnostic.clone();
            // Paths quoted inside messages and hints are shortened like the location line.
            if !base.as_os_str().is_empty() {
                diagnostic.message = diagnostic.message.replace(&prefix, "");
                diagnostic.hint = diagnostic.hint.map(|h| h.replace(&prefix, ""));
            }
            render_one(&mut out, &diagnostic, base);
            out.push('\n');
        }
        let (errors, warnings) = (self.error_count(), self.warning_count());
        let _ = writeln!(
            out,
            "{errors} error{}, {warnings} warning{}",
            plural(errors),
            plural(warnings)
        );
        out
    }

    /// One JSON object per diagnostic in an array, for CI annotations.
    pub fn render_json(&self) -> String {
        let items: Vec<JsonDiagnostic<'_>> = self
            .diagnostics
            .iter()
            .map(|d| {
                let position = d.location.as_ref().map(|l| {
                    let (line, column) = l.file.line_col(l.span.start);
                    let (end_line, end_column) = l.file.line_col(l.span.end);
                    (
                        l.file.path.display().to_string(),
                        line,
                        column,
                        end_line,
                        end_column,
                    )
                });
                JsonDiagnostic {
                    severity: d.severity,
                    code: d.code,
                    message: bounded(&d.message),
                    file: position.as_ref().map(|p| p.0.clone()),
                    line: position.as_ref().map(|p| p.1),
                    column: position.as_ref().map(|p| p.2),
                    end_line: position.as_ref().map(|p| p.3),
                    end_column: position.as_ref().map(|p| p.4),
                    hint: d.hint.as_deref().map(bounded),
                }
            })
            .collect();
        let mut summary = BTreeMap::new();
        summary.insert("errors", self.error_count());
        summary.insert("warnings", self.warning_count());
        serde_json::json!({ "diagnostics": items, "summary": summary }).to_string()
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

fn render_one(out: &mut String, diagnostic: &Diagnostic, base: &Path) {
    let label = match diagnostic.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    };
    let message = bounded(&diagnostic.message);
    let _ = writeln!(out, "{label}[{}]: {message}", diagnostic.code);
    let hint = diagnostic.hint.as_deref().map(bounded);
    if let Some(location) = &diagnostic.location {
        let file = &location.file;
        let (line, column) = file.line_col(location.span.start);
        let shown = file.path.strip_prefix(base).unwrap_or(&file.path);
        let gutter = line.to_string().len();
        let pad = " ".repeat(gutter);
        let _ = writeln!(out, "{pad}--> {}:{line}:{column}", shown.display());
        let _ = writeln!(out, "{pad} |");
        let text = file.line_text(line);
        let (end_line, end_column) = file.line_col(location.span.end);
        let width = if end_line == line {
            end_column.saturating_sub(column).max(1)
        } else {
            text.chars().count().saturating_sub(column - 1).max(1)
        };
        let excerpt = Excerpt::around(text, column - 1, width);
        let _ = writeln!(out, "{line} | {}", excerpt.text);
        let _ = writeln!(
            out,
            "{pad} | {}{}",
            " ".repeat(excerpt.caret_at),
            "^".repeat(excerpt.caret_width)
        );
        if let Some(hint) = &hint {
            let _ = writeln!(out, "{pad} = hint: {hint}");
        }
    } else if let Some(hint) = &hint {
        let _ = writeln!(out, "  = hint: {hint}");
    }
}

/// The most characters of a source line shown under a diagnostic; longer lines are cut
/// around the column (a minified or generated file can hold the whole file on one line).
/// Hand-written lines stay whole: the shipped formations' sample lines reach 180.
pub const EXCERPT_CHARS: usize = 200;
/// Characters kept before the column when a long line is cut.
const EXCERPT_LEAD: usize = 60;
/// The longest `quoted` run kept whole in a message (identifiers come from the input).
pub const MAX_QUOTE_CHARS: usize = 48;
/// The longest message or hint kept whole.
pub const MAX_MESSAGE_CHARS: usize = 400;
const ELLIPSIS: char = '…';

/// A window of one line and where the caret goes in it (in characters).
struct Excerpt<'a> {
    text: Cow<'a, str>,
    caret_at: usize,
    caret_width: usize,
}

impl<'a> Excerpt<'a> {
    /// The part of `line` around the 0-based character `column`, the caret `width` wide.
    fn around(line: &'a str, column: usize, width: usize) -> Self {
        // Byte length bounds the character count: short lines are shown whole without counting.
        let length = if line.len() <= EXCERPT_CHARS {
            line.chars().count()
        } else {
            line.chars().take(column + EXCERPT_CHARS + 1).count()
        };
        if length <= EXCERPT_CHARS {
            return Self {
                text: Cow::Borrowed(line),
                caret_at: column,
                caret_width: width,
            };
        }
        let start = column
            .saturating_sub(EXCERPT_LEAD)
            .min(length - EXCERPT_CHARS);
        let end = start + EXCERPT_CHARS;
        let mut text = String::new();
        if start > 0 {
            text.push(ELLIPSIS);
        }
        text.extend(line.chars().skip(start).take(EXCERPT_CHARS));
        if end < length {
            text.push(ELLIPSIS);
        }
        let caret_at = column - start + usize::from(start > 0);
        Self {
            text: Cow::Owned(text),
            caret_at,
            caret_width: width.min(end.saturating_sub(column)).max(1),
        }
    }
}

/// `text` with every `quoted` run longer than [`MAX_QUOTE_CHARS`] shortened with an ellipsis,
/// and the whole cut at [`MAX_MESSAGE_CHARS`]: messages quote names from the input, and a
/// 100,000-character identifier must not become a 100,000-character message.
pub fn bounded(text: &str) -> Cow<'_, str> {
    let long_quote =
        text.split('`').skip(1).step_by(2).any(|quoted| {
            quoted.len() > MAX_QUOTE_CHARS && quoted.chars().count() > MAX_QUOTE_CHARS
        });
    if !long_quote && text.len() <= MAX_MESSAGE_CHARS {
        return Cow::Borrowed(text);
    }
    let mut out = String::new();
    for (i, part) in text.split('`').enumerate() {
        if i > 0 {
            out.push('`');
        }
        if i % 2 == 1 && part.chars().count() > MAX_QUOTE_CHARS {
            out.extend(part.chars().take(MAX_QUOTE_CHARS));
            out.push(ELLIPSIS);
        } else {
            out.extend(part.chars().take(MAX_MESSAGE_CHARS + 1));
        }
        if out.len() > MAX_MESSAGE_CHARS * 4 {
            break;
        }
    }
    if out.chars().count() > MAX_MESSAGE_CHARS {
        out = out.chars().take(MAX_MESSAGE_CHARS).collect();
        out.push(ELLIPSIS);
    }
    Cow::Owned(out)
}

/// "did you mean `X`?" for the closest known name, if one is close enough to be a typo.
pub fn did_you_mean<'a>(unknown: &str, known: impl IntoIterator<Item = &'a str>) -> Option<String> {
    // Far longer than any name is no typo, and comparing it would cost time in its length.
    if unknown.len() > MAX_QUOTE_CHARS * 2 {
        return None;
    }
    let lower = unknown.to_lowercase();
    known
        .into_iter()
        .map(|candidate| {
            (
                strsim::jaro_winkler(&lower, &candidate.to_lowercase()),
                candidate,
            )
        })
        .filter(|(score, _)| *score >= 0.8)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, best)| format!("did you mean `{best}`?"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_caret_under_the_span() {
        let text = "Sequence([\n    Action(name: \"WalkToo\"),\n])\n".to_string();
        let file = Arc::new(SourceFile::new(PathBuf::from("behaviors/a.ron"), text));
        let start = file.text.find("\"WalkToo\"").unwrap();
        let mut report = Report::default();
        report.push(
            Diagnostic::error("unknown-node", "unknown node `WalkToo`")
                .at(&file, Span::new(start, start + 9))
                .maybe_hint(did_you_mean("WalkToo", ["Stand", "WalkTo"])),
        );
        let expected = "error[unknown-node]: unknown node `WalkToo`\n --> behaviors/a.ron:2:18\n  |\n2 |     Action(name: \"WalkToo\"),\n  |                  ^^^^^^^^^\n  = hint: did you mean `WalkTo`?\n\n1 error, 0 warnings\n";
        assert_eq!(report.render_text(), expected);
        let json: serde_json::Value = serde_json::from_str(&report.render_json()).unwrap();
        assert_eq!(json["diagnostics"][0]["line"], 2);
        assert_eq!(json["diagnostics"][0]["column"], 18);
        assert_eq!(json["summary"]["errors"], 1);
    }

    #[test]
    fn suggestions_only_for_close_names() {
        assert_eq!(
            did_you_mean("Sequnce", ["Sequence", "Fallback"]).as_deref(),
            Some("did you mean `Sequence`?")
        );
        assert_eq!(did_you_mean("Kick", ["Sequence", "Fallback"]), None);
    }

    /// The excerpt line and the caret line of a one-diagnostic rendering, as characters.
    fn excerpt_and_caret(rendered: &str) -> (Vec<char>, Vec<char>) {
        let lines: Vec<&str> = rendered.lines().collect();
        let (_, text) = lines[3].split_once(" | ").unwrap();
        let (_, caret) = lines[4].split_once(" | ").unwrap();
        (text.chars().collect(), caret.chars().collect())
    }

    #[test]
    fn a_long_line_is_cut_around_the_column_with_the_caret_still_under_it() {
        for (before, after) in [(100_000, 100_000), (3, 100_000), (100_000, 3), (150, 60)] {
            let text = format!("{}ÜX{}\n", "é".repeat(before), "b".repeat(after));
            let file = Arc::new(SourceFile::new(PathBuf::from("long.ron"), text));
            let start = file.text.find('X').unwrap();
            let mut report = Report::default();
            report.push(Diagnostic::error("x", "here").at(&file, Span::new(start, start + 3)));
            let rendered = report.render_text();
            assert!(rendered.len() < 1024, "{} bytes", rendered.len());
            let (excerpt, caret) = excerpt_and_caret(&rendered);
            assert!(excerpt.len() <= EXCERPT_CHARS + 2, "{}", excerpt.len());
            let at = caret.iter().position(|&c| c == '^').unwrap();
            assert_eq!(excerpt[at], 'X', "{rendered}");
            assert_eq!(excerpt[at - 1], 'Ü', "{rendered}");
            assert_eq!(caret.iter().filter(|&&c| c == '^').count(), 3);
            assert_eq!(excerpt.first() == Some(&'…'), before > EXCERPT_LEAD);
            assert_eq!(
                excerpt.last() == Some(&'…'),
                before + after > EXCERPT_CHARS && after > 100
            );
        }
    }

    #[test]
    fn long_quoted_names_and_long_messages_are_shortened() {
        let name = "N".repeat(100_000);
        let d = Diagnostic::error(
            "unknown-node",
            format!("unknown node `{name}`, see `{name}`"),
        );
        assert!(d.message.starts_with(&format!(
            "unknown node `{}…`, see `N",
            &name[..MAX_QUOTE_CHARS]
        )));
        assert!(d.message.chars().count() <= MAX_MESSAGE_CHARS + 1);
        let plain = "x".repeat(10_000);
        assert_eq!(bounded(&plain).chars().count(), MAX_MESSAGE_CHARS + 1);
        let short = "expected `,` or `)`, found `x`";
        assert!(matches!(bounded(short), Cow::Borrowed(s) if s == short));
        assert_eq!(did_you_mean(&name, ["N"]), None);
    }

    #[test]
    fn columns_count_characters() {
        let file = SourceFile::new(PathBuf::from("x"), "// é\n  \"ü\" x".into());
        let offset = file.text.rfind('x').unwrap();
        assert_eq!(file.line_col(offset), (2, 7));
    }
}
