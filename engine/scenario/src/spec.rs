//! What a scenario file says, after validation, and one concrete run drawn from it.

use libero_model::FieldGeometry;
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
    FromBall { dx: Num, dy: Num },
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
    /// cone bends rolls towards the field diagonals) so the roll ends on the line through it.
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
    /// The ball ends up at least `min_m` from where it was placed (it was kicked).
    BallMoved { min_m: f64 },
    /// No torso of ours ever closer than `min_distance_m` to another torso (ground plane).
    NoCollision { min_distance_m: f64 },
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
            Success::BallMoved { min_m } => format!("BallMoved(min_m: {min_m})"),
            Success::NoCollision { min_distance_m } => {
                format!("NoCollision(min_distance_m: {min_distance_m})")
            }
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

/// The launch heading [rad] from `from` towards `target` at `speed`, aimed off so that the
/// roll ends on the line through the target (the world model's launch table).
pub fn aimed_heading(ball: &BallParams, from: [f64; 2], target: [f64; 2], speed: f64) -> f64 {
    let bearing = (target[1] - from[1]).atan2(target[0] - from[0]);
    let rest = ball.launch_table.stop_offset(speed, bearing).norm();
    ball.launch_table.launch_heading_for(bearing, rest)
}

/// Where a ball launched at `speed` along `heading` [rad] from `from` comes to rest.
pub fn rest_point(ball: &BallParams, from: [f64; 2], speed: f64, heading: f64) -> [f64; 2] {
    let stop = ball.launch_table.stop_offset(speed, heading);
    [from[0] + stop.x, from[1] + stop.y]
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
