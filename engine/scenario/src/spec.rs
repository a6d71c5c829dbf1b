//! What a scenario file says, after validation, and one concrete run drawn from it.

use libero_model::FieldGeometry;
use libero_world::ball_launch::PATH_EXPONENT;
use libero_world::params::BallParams;

/// A number that is either fixed or drawn uniformly from a range for every run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Num {
    Fixed(f64),
    /// `Range(lo, hi)`, lo < hi.
    Range(f64, f64),
}

impl Num {
    pub fn lo(self) -> f64 {
        match self {
            Num::Fixed(v) | Num::Range(v, _) => v,
        }
    }

    pub fn hi(self) -> f64 {
        match self {
            Num::Fixed(v) | Num::Range(_, v) => v,
        }
    }

    pub fn draw(self, rng: &mut Rng) -> f64 {
        match self {
            Num::Fixed(v) => v,
            Num::Range(lo, hi) => lo + (hi - lo) * rng.uniform(),
        }
    }
}

/// A point in the global field frame (origin at the centre, +x towards the right goal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    pub x: Num,
    pub y: Num,
}

impl Point {
    pub fn draw(self, rng: &mut Rng) -> [f64; 2] {
        [self.x.draw(rng), self.y.draw(rng)]
    }
}

/// What drives a robot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Play {
    /// A Libero agent running its behavior tree (`behaviors/` + `formations/`).
    Tree,
    /// Stands where it was placed and looks around.
    Stand,
}

impl Play {
    pub fn name(self) -> &'static str {
        match self {
            Play::Tree => "Tree",
            Play::Stand => "Stand",
        }
    }
}

/// Where a robot is placed: a field point, or an offset from the ball's spot (drawn first), so
/// "behind the ball" stays behind it whatever the ball's draw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Place {
    At(Point),
    FromBall {
        dx: Num,
        dy: Num,
    },
    /// `distance_m` from the ball's spot in the field direction `bearing_deg` (0° = +x).
    AroundBall {
        distance_m: Num,
        bearing_deg: Num,
    },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    pub unum: u32,
    pub at: Place,
    pub heading_deg: Num,
    pub play: Play,
}

/// How the ball is set moving when the situation starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Launch {
    /// A speed along a field direction (0° = +x, 90° = +y).
    Velocity { speed_m_s: Num, direction_deg: Num },
    /// A speed towards a target point: aimed off for the ball's curve (rcssservermj's friction
    /// cone bends rolls towards the field diagonals) so the roll passes through it.
    Towards { target: Point, speed_m_s: Num },
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallSpec {
    pub at: Point,
    pub launch: Option<Launch>,
}

/// When a run counts as a success, judged from the server's ground truth.
#[derive(Debug, Clone, PartialEq)]
pub enum Success {
    /// Our team scores.
    GoalScored,
    /// No goal against us until the time limit (or until play stops).
    BallKeptOut,
    /// Our robot `unum`'s torso comes within `within_m` of the ball (ground plane).
    BallReached { unum: u32, within_m: f64 },
    /// After the ball is kicked, our robot `receiver` first touches it (torso within 0.4 m)
    /// within `within_m` of where the world model's ball tracker, fed the ground truth,
    /// predicted it would stop.
    PassReceived { receiver: u32, within_m: f64 },
    /// The ball ends up at least `min_m` from where it was placed (it was kicked).
    BallMoved { min_m: f64 },
    /// No torso of ours ever closer than `min_distance_m` to another torso (ground plane).
    NoCollision { min_distance_m: f64 },
    /// A kick sends the ball at least `min_m` from where it lay towards their goal, on a line
    /// that crosses their goal line between the posts.
    ShotOnTarget { min_m: f64 },
    /// Every part holds.
    All(Vec<Success>),
    /// At least one part holds.
    Any(Vec<Success>),
}

impl Success {
    /// The condition written back in the file's syntax.
    pub fn describe(&self) -> String {
        let list = |parts: &[Success]| {
            parts
                .iter()
                .map(Success::describe)
                .collect::<Vec<_>>()
                .join(", ")
        };
        match self {
            Success::GoalScored => "GoalScored".into(),
            Success::BallKeptOut => "BallKeptOut".into(),
            Success::BallReached { unum, within_m } => {
                format!("BallReached(unum: {unum}, within_m: {within_m})")
            }
            Success::PassReceived { receiver, within_m } => {
                format!("PassReceived(receiver: {receiver}, within_m: {within_m})")
            }
            Success::BallMoved { min_m } => format!("BallMoved(min_m: {min_m})"),
            Success::NoCollision { min_distance_m } => {
                format!("NoCollision(min_distance_m: {min_distance_m})")
            }
            Success::ShotOnTarget { min_m } => format!("ShotOnTarget(min_m: {min_m})"),
            Success::All(parts) => format!("All([{}])", list(parts)),
            Success::Any(parts) => format!("Any([{}])", list(parts)),
        }
    }
}

/// A validated scenario file.
#[derive(Debug, Clone)]
pub struct Scenario {
    pub name: String,
    pub field: FieldGeometry,
    /// Our team: plays from the left (own goal at −x).
    pub ours: Vec<Robot>,
    /// The other team: plays from the right.
    pub theirs: Vec<Robot>,
    pub ball: BallSpec,
    /// Seconds of simulated time after placement, ball at rest, before the ball is launched and
    /// judging starts (robots look around and localize).
    pub settle_s: f64,
    /// Seconds of simulated time from the launch until the run is judged.
    pub time_limit_s: f64,
    pub success: Success,
}

/// One robot's concrete placement: global x, y [m] and heading [deg].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    pub unum: u32,
    pub pose: [f64; 3],
    pub play: Play,
}

/// One run's concrete situation.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSetup {
    pub index: usize,
    pub ours: Vec<Placement>,
    pub theirs: Vec<Placement>,
    pub ball: [f64; 2],
    /// Launch velocity [m/s], global frame (zero without a launch).
    pub ball_velocity: [f64; 2],
    /// For `Towards` launches: the target point.
    pub target: Option<[f64; 2]>,
}

impl RunSetup {
    pub fn launch_speed(&self) -> f64 {
        self.ball_velocity[0].hypot(self.ball_velocity[1])
    }

    /// Field direction of the launch [deg].
    pub fn launch_direction_deg(&self) -> f64 {
        self.ball_velocity[1]
            .atan2(self.ball_velocity[0])
            .to_degrees()
    }
}

impl Scenario {
    /// Run `index` of a series seeded with `seed`: the same pair always gives the same
    /// situation, whatever the number of runs.
    pub fn draw(&self, seed: u64, index: usize, ball: &BallParams) -> RunSetup {
        let mut rng = Rng::new(seed ^ (index as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let at = self.ball.at.draw(&mut rng);
        let place = |robots: &[Robot], rng: &mut Rng| {
            robots
                .iter()
                .map(|r| {
                    let [x, y] = match r.at {
                        Place::At(p) => p.draw(rng),
                        Place::FromBall { dx, dy } => [at[0] + dx.draw(rng), at[1] + dy.draw(rng)],
                        Place::AroundBall {
                            distance_m,
                            bearing_deg,
                        } => {
                            let (d, b) = (distance_m.draw(rng), bearing_deg.draw(rng).to_radians());
                            [at[0] + d * b.cos(), at[1] + d * b.sin()]
                        }
                    };
                    Placement {
                        unum: r.unum,
                        pose: [x, y, r.heading_deg.draw(rng)],
                        play: r.play,
                    }
                })
                .collect::<Vec<_>>()
        };
        let ours = place(&self.ours, &mut rng);
        let theirs = place(&self.theirs, &mut rng);
        let (ball_velocity, target) = match self.ball.launch {
            None => ([0.0, 0.0], None),
            Some(Launch::Velocity {
                speed_m_s,
                direction_deg,
            }) => {
                let (v, d) = (speed_m_s.draw(&mut rng), direction_deg.draw(&mut rng));
                let d = d.to_radians();
                ([v * d.cos(), v * d.sin()], None)
            }
            Some(Launch::Towards { target, speed_m_s }) => {
                let t = target.draw(&mut rng);
                let v = speed_m_s.draw(&mut rng);
                let h = aimed_heading(ball, at, t, v);
                ([v * h.cos(), v * h.sin()], Some(t))
            }
        };
        RunSetup {
            index,
            ours,
            theirs,
            ball: at,
            ball_velocity,
            target,
        }
    }
}

/// The launch heading [rad] from `from` at `speed` whose roll passes through `target`.
///
/// rcssservermj's ball curves towards the field diagonals. The launch table gives where a roll
/// stops, `along` the launch direction and to its `left`; the path between is taken as a curve
/// tangent to the launch direction with left offset `left·(s/along)^PATH_EXPONENT` after `s`
/// metres. Falls back to the heading whose roll ends on the line through the target when no roll at
/// this speed gets there.
pub fn aimed_heading(ball: &BallParams, from: [f64; 2], target: [f64; 2], speed: f64) -> f64 {
    let table = &ball.launch_table;
    let (dx, dy) = (target[0] - from[0], target[1] - from[1]);
    let bearing = dy.atan2(dx);
    let miss = |h: f64| -> Option<f64> {
        let (along, left, a, b) = launch_frame(ball, [dx, dy], speed, h);
        (along > 0.0 && a > 0.0 && a <= along).then(|| b - left * (a / along).powf(PATH_EXPONENT))
    };
    let steps = (2.0 * AIM_OFF_MAX_DEG / AIM_STEP_DEG) as usize;
    let best = (0..=steps)
        .map(|k| bearing + (k as f64 * AIM_STEP_DEG - AIM_OFF_MAX_DEG).to_radians())
        .filter_map(|h| miss(h).map(|m| (h, m)))
        .min_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
    let Some((h, _)) = best else {
        let rest = table.stop_offset(speed, bearing).norm();
        return table.launch_heading_for(bearing, rest);
    };
    // Refine between the grid neighbours by the secant of the miss.
    let step = AIM_STEP_DEG.to_radians();
    match (miss(h - step), miss(h + step)) {
        (Some(ma), Some(mb)) if ma * mb < 0.0 && (mb - ma).abs() > 1e-12 => {
            (h - step - ma * 2.0 * step / (mb - ma)).clamp(h - step, h + step)
        }
        _ => h,
    }
}

/// Largest and step of the aim-off searched by [`aimed_heading`] [deg].
const AIM_OFF_MAX_DEG: f64 = 30.0;
const AIM_STEP_DEG: f64 = 0.1;

/// For a launch at `speed` along `heading` [rad]: the stop point `along` and to the `left` of
/// the launch direction, and the offset `d` (target minus launch point) in the same frame.
fn launch_frame(ball: &BallParams, d: [f64; 2], speed: f64, heading: f64) -> (f64, f64, f64, f64) {
    let stop = ball.launch_table.stop_offset(speed, heading);
    let (c, s) = (heading.cos(), heading.sin());
    (
        stop.x * c + stop.y * s,
        -stop.x * s + stop.y * c,
        d[0] * c + d[1] * s,
        -d[0] * s + d[1] * c,
    )
}

/// How far short of `target` a ball launched from `from` at `speed`, aimed by
/// [`aimed_heading`], stops [m] (≤ 0: its roll gets there).
pub fn shortfall(ball: &BallParams, from: [f64; 2], target: [f64; 2], speed: f64) -> f64 {
    let h = aimed_heading(ball, from, target, speed);
    let d = [target[0] - from[0], target[1] - from[1]];
    let (along, _, a, _) = launch_frame(ball, d, speed, h);
    a - along
}

/// Where a roll launched from `from` at `speed` along `heading` [rad] is after covering `s`
/// metres along the launch direction (the parabola of [`aimed_heading`]).
pub fn path_point(ball: &BallParams, from: [f64; 2], speed: f64, heading: f64, s: f64) -> [f64; 2] {
    let (along, left, _, _) = launch_frame(ball, [0.0, 0.0], speed, heading);
    let lateral = if along > 0.0 {
        left * (s / along).powf(PATH_EXPONENT)
    } else {
        0.0
    };
    let (c, sn) = (heading.cos(), heading.sin());
    [
        from[0] + s * c - lateral * sn,
        from[1] + s * sn + lateral * c,
    ]
}

/// A small seeded generator (SplitMix64): reproducible runs without a dependency.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}
