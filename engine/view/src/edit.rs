//! The formation editor's file side: formations read with the span of every sample and
//! position, edits made by replacing those spans (comments and layout kept), each edit checked
//! with `libero validate`'s checks before it is written.

use libero_behavior::files::{read_text, ron_files};
use libero_behavior::syntax::{parse, Body, Node, NodeKind, Span};
use libero_behavior::{Library, Report};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// A formation file as the editor shows it.
#[derive(Debug, Clone, Serialize)]
pub struct FormationDoc {
    /// The file's name inside the formations folder.
    pub file: String,
    pub name: String,
    pub roles: Vec<(u8, String)>,
    pub samples: Vec<SampleDoc>,
    #[serde(skip)]
    samples_span: Span,
}

#[derive(Debug, Clone, Serialize)]
pub struct SampleDoc {
    pub ball: [f64; 2],
    /// `(unum, position)` in file order.
    pub positions: Vec<(u8, [f64; 2])>,
    #[serde(skip)]
    span: Span,
    #[serde(skip)]
    position_spans: Vec<Span>,
}

/// Why an edit was not made. Nothing was written in any case.
#[derive(Debug)]
pub enum EditError {
    /// The request names something that is not there (file, sample, player).
    NotFound(String),
    /// The request itself is wrong (a path outside the folder, a number off the field).
    Refused(String),
    /// The edited file would not validate: the report as `libero validate` prints it.
    Invalid(String),
    Io(String),
}

impl std::fmt::Display for EditError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EditError::NotFound(m) | EditError::Refused(m) | EditError::Io(m) => f.write_str(m),
            EditError::Invalid(report) => write!(f, "the edit does not validate:\n{report}"),
        }
    }
}

fn pair(node: &Node) -> Option<[f64; 2]> {
    let number = |n: &Node| match n.kind {
        NodeKind::Float(v) => Some(v),
        NodeKind::Int(v) => Some(v as f64),
        _ => None,
    };
    match &node.kind {
        NodeKind::Struct {
            name: None,
            body: Body::Items(items),
        } if items.len() == 2 => Some([number(&items[0])?, number(&items[1])?]),
        _ => None,
    }
}

fn field<'a>(node: &'a Node, name: &str) -> Option<&'a Node> {
    match &node.kind {
        NodeKind::Struct {
            body: Body::Fields(fields),
            ..
        } => fields
            .iter()
            .find(|f| f.name.name == name)
            .map(|f| &f.value),
        _ => None,
    }
}

impl FormationDoc {
    /// Reads a `Formation(...)` file; `None` for any other kind of file.
    pub fn parse(file: &str, text: &str) -> Option<FormationDoc> {
        let root = parse(text).ok()?;
        match &root.kind {
            NodeKind::Struct { name: Some(n), .. } if n.name == "Formation" => {}
            _ => return None,
        }
        let name = match field(&root, "name").map(|n| &n.kind) {
            Some(NodeKind::Str(s)) => s.clone(),
            _ => file.trim_end_matches(".ron").to_string(),
        };
        let mut roles = Vec::new();
        if let Some(NodeKind::List(items)) = field(&root, "roles").map(|n| &n.kind) {
            for role in items {
                let unum = match field(role, "unum").map(|n| &n.kind) {
                    Some(NodeKind::Int(u)) => u8::try_from(*u).ok(),
                    _ => None,
                };
                let role_name = match field(role, "name").map(|n| &n.kind) {
                    Some(NodeKind::Str(s)) => s.clone(),
                    _ => String::new(),
                };
                if let Some(unum) = unum {
                    roles.push((unum, role_name));
                }
            }
        }
        let samples_node = field(&root, "samples")?;
        let NodeKind::List(items) = &samples_node.kind else {
            return None;
        };
        let mut samples = Vec::new();
        for sample in items {
            let ball = pair(field(sample, "ball")?)?;
            let NodeKind::Map(entries) = &field(sample, "positions")?.kind else {
                return None;
            };
            let mut positions = Vec::new();
            let mut position_spans = Vec::new();
            for (key, value) in entries {
                let NodeKind::Int(unum) = key.kind else {
                    return None;
                };
                positions.push((u8::try_from(unum).ok()?, pair(value)?));
                position_spans.push(value.span);
            }
            samples.push(SampleDoc {
                ball,
                positions,
                span: sample.span,
                position_spans,
            });
        }
        Some(FormationDoc {
            file: file.to_string(),
            name,
            roles,
            samples,
            samples_span: samples_node.span,
        })
    }

    /// The text with player `unum`'s position in sample `sample` set to `at` (only that
    /// tuple's characters change).
    pub fn move_player(
        &self,
        text: &str,
        sample: usize,
        unum: u8,
        at: [f64; 2],
    ) -> Result<String, EditError> {
        let s = self
            .samples
            .get(sample)
            .ok_or_else(|| EditError::NotFound(format!("{} has no sample {sample}", self.file)))?;
        let k = s
            .positions
            .iter()
            .position(|(u, _)| *u == unum)
            .ok_or_else(|| {
                EditError::NotFound(format!(
                    "sample {sample} of {} has no player {unum}",
                    self.file
                ))
            })?;
        Ok(splice(text, s.position_spans[k], &tuple(at)))
    }

    /// The text with a new sample for a ball at `ball`, its positions copied from the sample
    /// nearest that ball, written after the last sample in the same layout.
    pub fn add_sample(&self, text: &str, ball: [f64; 2]) -> Result<String, EditError> {
        let nearest = self
            .samples
            .iter()
            .min_by(|a, b| dist(a.ball, ball).total_cmp(&dist(b.ball, ball)))
            .ok_or_else(|| EditError::NotFound(format!("{} has no sample to copy", self.file)))?;
        let last = self.samples.last().map_or(self.samples_span, |s| s.span);
        let positions: Vec<String> = nearest
            .positions
            .iter()
            .map(|(u, p)| format!("{u}: {}", tuple(*p)))
            .collect();
        let line_start = text[..last.start].rfind('\n').map_or(0, |i| i + 1);
        let indent: String = text[line_start..last.start]
            .chars()
            .take_while(|c| c.is_whitespace())
            .collect();
        let entry = format!(
            "{indent}Sample(ball: {}, positions: {{ {} }})",
            tuple(ball),
            positions.join(", ")
        );
        // After the last sample: behind its comma when it has one (keeping a trailing comma).
        let rest = &text[last.end..];
        Ok(if rest.trim_start().starts_with(',') {
            let at = last.end + rest.find(',').unwrap_or(0) + 1;
            format!("{}\n{entry},{}", &text[..at], &text[at..])
        } else {
            format!("{},\n{entry}{}", &text[..last.end], rest)
        })
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// A position as the shipped files write it: one decimal, or two when finer.
pub fn tuple([x, y]: [f64; 2]) -> String {
    let one = |v: f64| {
        let v = (v * 100.0).round() / 100.0;
        if (v * 10.0).fract().abs() < 1e-9 {
            format!("{v:.1}")
        } else {
            format!("{v:.2}")
        }
    };
    format!("({}, {})", one(x), one(y))
}

fn splice(text: &str, span: Span, with: &str) -> String {
    format!("{}{}{}", &text[..span.start], with, &text[span.end..])
}

/// The folders a team's library is read from and the one folder edits may write into.
#[derive(Debug, Clone)]
pub struct EditTarget {
    /// Every folder of the team's library (behaviors and formations): an edit is validated
    /// against all of them, as `libero validate` would.
    pub library_dirs: Vec<PathBuf>,
    /// The formations folder: the only place the editor writes.
    pub formations: PathBuf,
}

impl EditTarget {
    /// The path of `file` inside the formations folder, refusing anything else: names with a
    /// separator or `..`, links, files that are not already there.
    pub fn resolve(&self, file: &str) -> Result<PathBuf, EditError> {
        if file.is_empty()
            || file.contains(['/', '\\'])
            || file.starts_with('.')
            || !file.ends_with(".ron")
        {
            return Err(EditError::Refused(format!(
                "`{file}` is not a file name in the formations folder"
            )));
        }
        let folder = self
            .formations
            .canonicalize()
            .map_err(|e| EditError::Io(format!("{}: {e}", self.formations.display())))?;
        let path = folder.join(file);
        let meta = std::fs::symlink_metadata(&path)
            .map_err(|_| EditError::NotFound(format!("no formation file `{file}`")))?;
        if !meta.is_file() {
            return Err(EditError::Refused(format!(
                "`{file}` is not a regular file (links are not edited)"
            )));
        }
        Ok(path)
    }

    /// Every formation file of the folder, read for the editor.
    pub fn formations(&self) -> Vec<FormationDoc> {
        let mut report = Report::default();
        let folder = self.formations.canonicalize().ok();
        let mut docs: Vec<FormationDoc> =
            ron_files(std::slice::from_ref(&self.formations), &mut report)
                .into_iter()
                .filter(|p| p.parent().and_then(|d| d.canonicalize().ok()) == folder)
                .filter_map(|path| {
                    let name = path.file_name()?.to_str()?.to_string();
                    let text = read_text(&path).ok()?;
                    FormationDoc::parse(&name, &text)
                })
                .collect();
        docs.sort_by(|a, b| a.file.cmp(&b.file));
        docs
    }

    /// Apply `edit` to `file`'s text, validate the whole library with the new text, and write
    /// it (through a temporary file and a rename, so the watcher never reads half a file).
    pub fn apply(
        &self,
        file: &str,
        edit: impl FnOnce(&FormationDoc, &str) -> Result<String, EditError>,
    ) -> Result<FormationDoc, EditError> {
        let path = self.resolve(file)?;
        let text = read_text(&path).map_err(|e| EditError::Io(e.describe(&path)))?;
        let doc = FormationDoc::parse(file, &text)
            .ok_or_else(|| EditError::Refused(format!("`{file}` is not a formation file")))?;
        let edited = edit(&doc, &text)?;
        self.validate_with(&path, &edited)?;
        let temporary = path.with_file_name(format!(".{file}.libero-edit"));
        std::fs::write(&temporary, &edited)
            .and_then(|()| std::fs::rename(&temporary, &path))
            .map_err(|e| {
                let _ = std::fs::remove_file(&temporary);
                EditError::Io(format!("cannot write {}: {e}", path.display()))
            })?;
        FormationDoc::parse(file, &edited)
            .ok_or_else(|| EditError::Io(format!("{file} unreadable after the edit")))
    }

    /// `libero validate`'s checks on the team's files with `path` holding `text`.
    fn validate_with(&self, path: &Path, text: &str) -> Result<(), EditError> {
        let mut report = Report::default();
        let files = ron_files(&self.library_dirs, &mut report);
        let canonical = path.canonicalize().ok();
        let mut texts: Vec<(String, String)> = Vec::new();
        for file in files {
            let content = if file.canonicalize().ok() == canonical {
                text.to_string()
            } else {
                read_text(&file).map_err(|e| EditError::Io(e.describe(&file)))?
            };
            texts.push((file.display().to_string(), content));
        }
        let borrowed: Vec<(&str, &str)> = texts
            .iter()
            .map(|(p, t)| (p.as_str(), t.as_str()))
            .collect();
        match Library::from_texts(
            &borrowed,
            &libero_strategy::vocabulary(),
            &libero_strategy::StrategyFiles,
        ) {
            Ok(_) => Ok(()),
            Err(report) => Err(EditError::Invalid(report.render_text())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r#"// A comment that must survive.
Formation(
    name: "mini",
    field: "fifa7vs7",
    roles: [
        Role(unum: 1, name: "goalkeeper", attraction: (0.0, 0.0)),
        Role(unum: 2, name: "back", attraction: (0.0, 0.0)),
    ],
    samples: [
        // the middle
        Sample(ball: (0.0, 0.0), positions: { 1: (-24.0, 0.0), 2: (-10.0, 0.0) }),
        Sample(ball: (10.0, 5.0), positions: { 1: (-23.0, 1.0),  2: (-2.0, 3.0) }),
    ],
)
"#;

    #[test]
    fn a_formation_is_read_with_its_samples() {
        let doc = FormationDoc::parse("mini.ron", TEXT).unwrap();
        assert_eq!(doc.name, "mini");
        assert_eq!(
            doc.roles,
            vec![(1, "goalkeeper".into()), (2, "back".into())]
        );
        assert_eq!(doc.samples.len(), 2);
        assert_eq!(doc.samples[1].ball, [10.0, 5.0]);
        assert_eq!(
            doc.samples[1].positions,
            vec![(1, [-23.0, 1.0]), (2, [-2.0, 3.0])]
        );
    }

    #[test]
    fn moving_a_player_changes_only_its_tuple() {
        let doc = FormationDoc::parse("mini.ron", TEXT).unwrap();
        let edited = doc.move_player(TEXT, 1, 2, [-3.25, 4.0]).unwrap();
        assert_eq!(
            edited,
            TEXT.replace("2: (-2.0, 3.0)", "2: (-3.25, 4.0)"),
            "comments, spacing and every other number stay"
        );
        let again = FormationDoc::parse("mini.ron", &edited).unwrap();
        assert_eq!(again.samples[1].positions[1], (2, [-3.25, 4.0]));
        assert!(doc.move_player(TEXT, 2, 2, [0.0, 0.0]).is_err());
        assert!(doc.move_player(TEXT, 0, 7, [0.0, 0.0]).is_err());
    }

    #[test]
    fn an_added_sample_copies_the_nearest_and_keeps_the_layout() {
        let doc = FormationDoc::parse("mini.ron", TEXT).unwrap();
        let edited = doc.add_sample(TEXT, [12.0, 6.0]).unwrap();
        let again = FormationDoc::parse("mini.ron", &edited).unwrap();
        assert_eq!(again.samples.len(), 3);
        assert_eq!(again.samples[2].ball, [12.0, 6.0]);
        assert_eq!(again.samples[2].positions, doc.samples[1].positions);
        assert!(edited.contains("// the middle") && edited.starts_with("// A comment"));
        assert!(edited.contains(
            "\n        Sample(ball: (12.0, 6.0), positions: { 1: (-23.0, 1.0), 2: (-2.0, 3.0) }),\n    ],"
        ), "{edited}");
    }

    #[test]
    fn only_plain_files_inside_the_formations_folder_resolve() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("mini.ron"), TEXT).unwrap();
        let target = EditTarget {
            library_dirs: vec![dir.path().to_path_buf()],
            formations: dir.path().to_path_buf(),
        };
        assert!(target.resolve("mini.ron").is_ok());
        for bad in [
            "../mini.ron",
            "/etc/passwd",
            "sub/mini.ron",
            ".hidden.ron",
            "mini.txt",
            "other.ron",
        ] {
            assert!(target.resolve(bad).is_err(), "{bad} resolved");
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("/etc/hostname", dir.path().join("link.ron")).unwrap();
            assert!(target.resolve("link.ron").is_err(), "a link is not edited");
        }
    }
}
