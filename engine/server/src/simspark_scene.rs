//! Ground truth from SimSpark's monitor stream: the scene graph, kept up to date.
//!
//! A full frame `(env)(RSG 0 1)((nd TRF (SLT m0 … m15) …) …)` describes every node; the updates
//! between them, `(env)(RDS 0 1)((nd (SLT …) …) …)`, mirror the same tree with only what
//! changed (a moved node's `SLT`, nothing for the rest: `(nd)`). So the tree of the last full
//! frame is kept and each update is walked beside it, child by child. `SLT` is a 4 × 4
//! column-major transform relative to the parent, translation in elements 12–14.
//!
//! A robot is a top-level node whose subtree holds the torso mesh `models/naobody<T>.obj`; the
//! torso mesh's materials name the uniform number (`matNum<N>`) and the side (`matLeft` /
//! `matRight`). The ball is the node holding `models/soccerball.obj`.

use libero_protocol::sexp::{self, List};

/// One robot as the server has it (tests and evaluation only).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotTruth {
    pub left: bool,
    pub unum: u32,
    /// Torso centre [m], world frame.
    pub torso: [f64; 3],
    /// The z component of the torso's up axis: 1 upright, 0 lying.
    pub up: f64,
    /// The torso's rotation, column-major: its x (right), y (forward) and z (up) axes in the
    /// world frame (SimSpark's body convention).
    pub rotation: [f64; 9],
}

impl RobotTruth {
    /// The torso's orientation as Libero's models have it (x forward, y left, z up) in the
    /// world frame, as a unit quaternion (w, x, y, z).
    pub fn orientation(&self) -> [f64; 4] {
        let r = &self.rotation;
        let column = |c: usize| [r[3 * c], r[3 * c + 1], r[3 * c + 2]];
        let (right, forward, up) = (column(0), column(1), column(2));
        let left = [-right[0], -right[1], -right[2]];
        // Rotation matrix with columns forward, left, up; element (row, col).
        let m = |row: usize, col: usize| [forward, left, up][col][row];
        quaternion_of(m)
    }
}

/// A unit quaternion (w, x, y, z) from a rotation matrix (Shepperd's method).
fn quaternion_of(m: impl Fn(usize, usize) -> f64) -> [f64; 4] {
    let trace = m(0, 0) + m(1, 1) + m(2, 2);
    let q = if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        [
            s / 4.0,
            (m(2, 1) - m(1, 2)) / s,
            (m(0, 2) - m(2, 0)) / s,
            (m(1, 0) - m(0, 1)) / s,
        ]
    } else if m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2) {
        let s = (1.0 + m(0, 0) - m(1, 1) - m(2, 2)).sqrt() * 2.0;
        [
            (m(2, 1) - m(1, 2)) / s,
            s / 4.0,
            (m(0, 1) + m(1, 0)) / s,
            (m(0, 2) + m(2, 0)) / s,
        ]
    } else if m(1, 1) > m(2, 2) {
        let s = (1.0 + m(1, 1) - m(0, 0) - m(2, 2)).sqrt() * 2.0;
        [
            (m(0, 2) - m(2, 0)) / s,
            (m(0, 1) + m(1, 0)) / s,
            s / 4.0,
            (m(1, 2) + m(2, 1)) / s,
        ]
    } else {
        let s = (1.0 + m(2, 2) - m(0, 0) - m(1, 1)).sqrt() * 2.0;
        [
            (m(1, 0) - m(0, 1)) / s,
            (m(0, 2) + m(2, 0)) / s,
            (m(1, 2) + m(2, 1)) / s,
            s / 4.0,
        ]
    };
    let norm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    q.map(|v| v / norm)
}

#[derive(Debug, Clone, Default)]
struct SceneNode {
    transform: Option<[f64; 16]>,
    mesh: Option<String>,
    materials: Vec<String>,
    children: Vec<SceneNode>,
}

/// The scene graph of the latest full frame with every later update applied.
#[derive(Debug, Clone, Default)]
pub struct SceneTracker {
    roots: Vec<SceneNode>,
    /// Whether a full frame has been seen (updates before one cannot be placed).
    complete: bool,
}

impl SceneTracker {
    /// Apply one monitor frame; returns whether it carried a scene graph that was applied.
    pub fn update(&mut self, frame: &str) -> bool {
        let mut items = sexp::top_level(frame);
        let (Some(Ok(_env)), Some(Ok(marker)), Some(Ok(scene))) =
            (items.next(), items.next(), items.next())
        else {
            return false;
        };
        let (Some(marker), Some(scene)) = (marker.as_list(), scene.as_list()) else {
            return false;
        };
        match marker.head() {
            Some("RSG") => {
                self.roots = nodes_of(scene).map(|n| full_node(n, 0)).collect();
                self.complete = true;
                true
            }
            Some("RDS") if self.complete => {
                for (node, diff) in self.roots.iter_mut().zip(nodes_of(scene)) {
                    apply_diff(node, diff, 0);
                }
                true
            }
            _ => false,
        }
    }

    /// The ball's centre [m], world frame.
    pub fn ball(&self) -> Option<[f64; 3]> {
        let mut found = None;
        for root in &self.roots {
            visit(root, IDENTITY, &mut |node, world| {
                if found.is_none()
                    && node
                        .mesh
                        .as_deref()
                        .is_some_and(|m| m.ends_with("soccerball.obj"))
                {
                    found = Some([world[12], world[13], world[14]]);
                }
            });
        }
        found
    }

    /// Every robot with a torso in the scene. The torso body is the node two levels above the
    /// torso mesh: the level between turns the mesh into the body's frame (identity in older
    /// builds, a quarter turn about x in this one), so the body's own transform is the truth.
    pub fn robots(&self) -> Vec<RobotTruth> {
        let mut robots = Vec::new();
        for root in &self.roots {
            visit(root, IDENTITY, &mut |node, world| {
                let Some(materials) = torso_materials(node) else {
                    return;
                };
                let unum = materials
                    .iter()
                    .find_map(|m| m.strip_prefix("matNum")?.parse().ok());
                let left = materials.iter().any(|m| m == "matLeft");
                let right = materials.iter().any(|m| m == "matRight");
                if let (Some(unum), true) = (unum, left || right) {
                    robots.push(RobotTruth {
                        left,
                        unum,
                        torso: [world[12], world[13], world[14]],
                        up: world[10],
                        rotation: [
                            world[0], world[1], world[2], world[4], world[5], world[6], world[8],
                            world[9], world[10],
                        ],
                    });
                }
            });
        }
        robots
    }
}

/// The torso mesh's materials when `node` is a torso body: a child holding the mesh
/// `models/naobody<T>.obj` directly below it.
fn torso_materials(node: &SceneNode) -> Option<&[String]> {
    node.transform?;
    node.children.iter().find_map(|frame| {
        frame.children.iter().find_map(|mesh| {
            let file = mesh.mesh.as_deref()?.rsplit('/').next()?;
            file.starts_with("naobody")
                .then_some(mesh.materials.as_slice())
        })
    })
}

const IDENTITY: [f64; 16] = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

/// Call `f` on every node with its world transform.
fn visit(node: &SceneNode, parent: [f64; 16], f: &mut impl FnMut(&SceneNode, &[f64; 16])) {
    let world = match &node.transform {
        Some(local) => multiply(&parent, local),
        None => parent,
    };
    f(node, &world);
    for child in &node.children {
        visit(child, world, f);
    }
}

/// `a · b` for column-major 4 × 4 matrices.
fn multiply(a: &[f64; 16], b: &[f64; 16]) -> [f64; 16] {
    let mut out = [0.0; 16];
    for col in 0..4 {
        for row in 0..4 {
            out[col * 4 + row] = (0..4).map(|k| a[k * 4 + row] * b[col * 4 + k]).sum();
        }
    }
    out
}

fn nodes_of(list: List<'_>) -> impl Iterator<Item = List<'_>> {
    list.iter()
        .filter_map(|c| c.as_list())
        .filter(|c| c.head() == Some("nd"))
}

/// Scene graphs are a few levels deep; anything deeper is left out rather than recursed into.
const MAX_DEPTH: usize = 32;

/// A node of a full frame: `(nd TRF (SLT …) (nd …)…)`, `(nd StaticMesh … (load M) (resetMaterials …))`.
fn full_node(list: List<'_>, depth: usize) -> SceneNode {
    let mut node = SceneNode::default();
    for child in list.tail() {
        let Some(item) = child.as_list() else {
            continue;
        };
        match item.head() {
            Some("nd") if depth < MAX_DEPTH => node.children.push(full_node(item, depth + 1)),
            Some("SLT") => node.transform = item.tail_numbers::<16>(),
            Some("load") => {
                node.mesh = item
                    .tail()
                    .next()
                    .and_then(|a| a.as_atom())
                    .map(str::to_string)
            }
            Some("resetMaterials") => {
                node.materials = item
                    .tail()
                    .filter_map(|a| a.as_atom())
                    .map(str::to_string)
                    .collect()
            }
            _ => {}
        }
    }
    node
}

/// Walk an update beside the kept node: a new `SLT` replaces the old; children pair up in order.
fn apply_diff(node: &mut SceneNode, diff: List<'_>, depth: usize) {
    let mut children = node.children.iter_mut();
    for item in diff.tail().filter_map(|c| c.as_list()) {
        match item.head() {
            Some("SLT") => {
                if let Some(m) = item.tail_numbers::<16>() {
                    node.transform = Some(m);
                }
            }
            Some("nd") => match children.next() {
                Some(child) if depth < MAX_DEPTH => apply_diff(child, item, depth + 1),
                _ => return,
            },
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(n: usize) -> String {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../../shared/samples/simspark/monitor_first.txt"
        );
        let text = std::fs::read_to_string(path).unwrap();
        // Messages alternate a `### monitor message #k` line and the message itself.
        text.lines()
            .filter(|l| !l.starts_with("###") && !l.trim().is_empty())
            .nth(n)
            .unwrap()
            .to_string()
    }

    #[test]
    fn robots_and_ball_from_a_real_full_frame() {
        let mut scene = SceneTracker::default();
        assert!(scene.update(&sample(0)));
        let ball = scene.ball().unwrap();
        assert!((ball[2] - 0.0417605).abs() < 1e-9 && ball[0] == 0.0);
        let robots = scene.robots();
        assert_eq!(robots.len(), 2, "{robots:?}");
        let left = robots.iter().find(|r| r.left).unwrap();
        let right = robots.iter().find(|r| !r.left).unwrap();
        assert_eq!((left.unum, right.unum), (1, 1));
        // The torso transforms of the sample (parents are identities).
        assert!((left.torso[0] + 5.27009).abs() < 1e-6, "{left:?}");
        assert!((right.torso[2] - 0.383392).abs() < 1e-6, "{right:?}");
        // The left robot was tipping over in the sample: its up axis is far from vertical.
        assert!(left.up < 0.9 && left.up > -1.0);
    }

    #[test]
    fn updates_move_only_what_they_name() {
        let mut scene = SceneTracker::default();
        // An update before any full frame cannot be placed.
        assert!(!scene.update(&sample(1)));
        assert!(scene.update(&sample(0)));
        let before = scene.robots();
        assert!(scene.update(&sample(1)));
        let after = scene.robots();
        let left = |rs: &[RobotTruth]| *rs.iter().find(|r| r.left).unwrap();
        // The sample's second message moves the left torso to (-5.30186, -0.0386229, 0.346039).
        assert!(
            (left(&after).torso[0] + 5.30186).abs() < 1e-6,
            "{:?}",
            left(&after)
        );
        assert_ne!(left(&before).torso, left(&after).torso);
        assert_eq!(scene.ball(), Some([0.0, 0.0, 0.0417605]));
    }

    #[test]
    fn garbage_and_deep_nesting_are_survived() {
        let mut scene = SceneTracker::default();
        assert!(!scene.update("(((((("));
        assert!(!scene.update("not a frame"));
        let deep = format!(
            "()(RSG 0 1)({}{})",
            "(nd TRF (SLT 1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1)".repeat(10_000),
            ")".repeat(10_000)
        );
        assert!(scene.update(&deep));
        assert!(scene.robots().is_empty() && scene.ball().is_none());
    }

    #[test]
    fn orientation_in_libero_axes() {
        let robot = |rotation| RobotTruth {
            left: true,
            unum: 1,
            torso: [0.0; 3],
            up: 1.0,
            rotation,
        };
        // Upright, facing world +y (SimSpark's forward axis along world y): no turn at all in
        // SimSpark's terms, a quarter turn left in ours (our x forward).
        let facing_y = robot([1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        let [w, x, y, z] = facing_y.orientation();
        let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
        assert!((yaw.to_degrees() - 90.0).abs() < 1e-9, "{yaw}");
        // Facing world +x: body forward (column 1) = +x, right (column 0) = -y.
        let facing_x = robot([0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
        let q = facing_x.orientation();
        assert!((q[0].abs() - 1.0).abs() < 1e-9, "{q:?}");
    }

    #[test]
    fn composition_of_transforms() {
        let mut shift = IDENTITY;
        shift[12] = 1.0;
        // A quarter turn about z, then the shift in the turned frame.
        let turn = [
            0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ];
        let m = multiply(&turn, &shift);
        assert!((m[12] - 0.0).abs() < 1e-12 && (m[13] - 1.0).abs() < 1e-12);
    }
}
