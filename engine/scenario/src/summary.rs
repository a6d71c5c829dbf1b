//! Run outcomes and the series summary: text (one figure per line) and JSON.

use crate::spec::{Placement, RunSetup};
use serde::Serialize;

/// The ball's launch as the ground truth shows it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LaunchMeasure {
    /// Direction of the first 0.3 s of travel [deg, field frame].
    pub direction_deg: f64,
    /// Mean speed over that time [m/s] (the ball slows down ~3.4 m/s² while sliding).
    pub mean_speed_m_s: f64,
}

/// The median of `times` (sorted here); `None` for none.
fn median(mut t: Vec<f64>) -> Option<f64> {
    t.sort_by(f64::total_cmp);
    match t.len() {
        0 => None,
        n if n % 2 == 1 => Some(t[n / 2]),
        n => Some(0.5 * (t[n / 2 - 1] + t[n / 2])),
    }
}

/// The median of `times`, a `None` counting as longer than any time; `None` if that median
/// is one.
pub fn median_with_never(times: impl Iterator<Item = Option<f64>>) -> Option<f64> {
    median(times.map(|t| t.unwrap_or(f64::INFINITY)).collect()).filter(|m| m.is_finite())
}

/// A torso higher than this stands (walking height is about 0.6 m, lying below 0.3 m).
pub(crate) const STANDING_TORSO_Z_M: f64 = 0.5;
/// A torso lower than this has fallen (counted again once it stood up).
const FALLEN_TORSO_Z_M: f64 = 0.35;

/// Falls per robot from its torso's ground-truth height.
pub(crate) struct FallCounter {
    down: Vec<bool>,
    falls: Vec<u32>,
}

impl FallCounter {
    pub(crate) fn new(robots: usize) -> Self {
        Self {
            down: vec![false; robots],
            falls: vec![0; robots],
        }
    }

    /// Robot `i`'s torso height now [m], if known.
    pub(crate) fn observe(&mut self, i: usize, torso_z: Option<f64>) {
        let Some(z) = torso_z else { return };
        if !self.down[i] && z < FALLEN_TORSO_Z_M {
            self.down[i] = true;
            self.falls[i] += 1;
        } else if z > STANDING_TORSO_Z_M {
            self.down[i] = false;
        }
    }

    pub(crate) fn of(&self, i: usize) -> u32 {
        self.falls[i]
    }
}

/// Where a robot was at the launch and at the end of the run, and how often it fell on the
/// way (ground truth).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RobotTravel {
    pub ours: bool,
    pub unum: u32,
    pub from: [f64; 2],
    pub to: [f64; 2],
    pub falls: u32,
}

impl RobotTravel {
    pub fn distance_m(&self) -> f64 {
        (self.to[0] - self.from[0]).hypot(self.to[1] - self.from[1])
    }
}

/// One run's result.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    pub index: usize,
    pub success: bool,
    /// Seconds from the launch until the condition was met.
    pub time_s: Option<f64>,
    /// Why it failed.
    pub why: Option<String>,
    /// How the run ended (condition met or broken, play stopped, time ran out).
    pub ended: String,
    pub setup: RunSetup,
    /// `None`: the ball was never seen moving (no launch, or it was not carried out).
    pub launch: Option<LaunchMeasure>,
    pub goals_for: u32,
    pub goals_against: u32,
    /// Closest approach of two torsos [m].
    pub closest_m: Option<f64>,
    /// Seconds from the launch until one of our torsos first came within reach of the ball.
    pub first_touch_s: Option<f64>,
    /// Farthest the ball got from its placement [m].
    pub ball_travel_m: f64,
    /// Where the ball first crossed a goal line (y [m]), if it did.
    pub goal_line_y: Option<f64>,
    /// The last ball position seen in play (before the referee moved it after a goal or out).
    pub ball_end: Option<[f64; 2]>,
    /// Every robot's start and end.
    pub robots: Vec<RobotTravel>,
}

#[derive(Serialize)]
struct JsonPlacement {
    unum: u32,
    x: f64,
    y: f64,
    heading_deg: f64,
    play: &'static str,
}

fn placements(list: &[Placement]) -> Vec<JsonPlacement> {
    list.iter()
        .map(|p| JsonPlacement {
            unum: p.unum,
            x: p.pose[0],
            y: p.pose[1],
            heading_deg: p.pose[2],
            play: p.play.name(),
        })
        .collect()
}

#[derive(Serialize)]
struct JsonRun {
    index: usize,
    success: bool,
    time_s: Option<f64>,
    why: Option<String>,
    ended: String,
    ball: [f64; 2],
    launch_velocity: [f64; 2],
    launch_speed_m_s: f64,
    launch_direction_deg: f64,
    target: Option<[f64; 2]>,
    measured_launch: Option<LaunchMeasure>,
    ball_travel_m: f64,
    goal_line_y: Option<f64>,
    ball_end: Option<[f64; 2]>,
    goals_for: u32,
    goals_against: u32,
    closest_m: Option<f64>,
    first_touch_s: Option<f64>,
    robots: Vec<RobotTravel>,
    ours: Vec<JsonPlacement>,
    theirs: Vec<JsonPlacement>,
}

#[derive(Serialize)]
struct JsonSummary<'a> {
    scenario: &'a str,
    file: &'a str,
    success_condition: &'a str,
    seed: u64,
    runs: usize,
    successes: usize,
    success_rate: f64,
    median_time_s: Option<f64>,
    median_time_all_runs_s: Option<f64>,
    median_first_touch_s: Option<f64>,
    mean_time_s: Option<f64>,
    wall_s: f64,
    per_run: Vec<JsonRun>,
}

/// A finished series.
#[derive(Debug, Clone)]
pub struct Summary {
    pub scenario: String,
    pub file: String,
    pub condition: String,
    pub seed: u64,
    pub runs: Vec<RunOutcome>,
    pub wall_s: f64,
}

impl Summary {
    pub fn successes(&self) -> usize {
        self.runs.iter().filter(|r| r.success).count()
    }

    pub fn success_rate(&self) -> f64 {
        if self.runs.is_empty() {
            0.0
        } else {
            self.successes() as f64 / self.runs.len() as f64
        }
    }

    fn times(&self) -> Vec<f64> {
        let mut t: Vec<f64> = self.runs.iter().filter_map(|r| r.time_s).collect();
        t.sort_by(f64::total_cmp);
        t
    }

    pub fn median_time_s(&self) -> Option<f64> {
        median(self.times())
    }

    /// The median over every run, a failure counting as never: `None` when at least half
    /// the runs failed (or there are none).
    pub fn median_time_all_runs_s(&self) -> Option<f64> {
        median_with_never(self.runs.iter().map(|r| r.time_s))
    }

    /// The median time to our first touch of the ball over every run, a run without one
    /// counting as never.
    pub fn median_first_touch_s(&self) -> Option<f64> {
        median_with_never(self.runs.iter().map(|r| r.first_touch_s))
    }

    pub fn mean_time_s(&self) -> Option<f64> {
        let t = self.times();
        (!t.is_empty()).then(|| t.iter().sum::<f64>() / t.len() as f64)
    }

    /// One line per run.
    pub fn run_line(r: &RunOutcome) -> String {
        let s = &r.setup;
        let mut line = format!(
            "run {:2}: {}  ball ({:.2}, {:.2})",
            r.index + 1,
            if r.success { "success" } else { "FAIL   " },
            s.ball[0],
            s.ball[1]
        );
        if s.launch_speed() > 0.0 {
            line.push_str(&format!(
                " launched {:.2} m/s at {:.1}°",
                s.launch_speed(),
                s.launch_direction_deg()
            ));
            match r.launch {
                Some(m) => line.push_str(&format!(
                    " (measured {:.1}°, {:.2} m/s over 0.3 s)",
                    m.direction_deg, m.mean_speed_m_s
                )),
                None => line.push_str(" (NOT seen moving)"),
            }
        }
        if let Some(t) = r.time_s {
            line.push_str(&format!("  in {t:.2} s"));
        }
        line.push_str(&format!("  [{}]", r.ended));
        if let Some(why) = &r.why {
            line.push_str(&format!(": {why}"));
        }
        line.push_str(&format!(
            "  goals {}-{}, ball travel {:.1} m",
            r.goals_for, r.goals_against, r.ball_travel_m
        ));
        if let Some([x, y]) = r.ball_end {
            line.push_str(&format!(", last in play at ({x:.2}, {y:.2})"));
        }
        if let Some(y) = r.goal_line_y {
            line.push_str(&format!(", crossed a goal line at y = {y:.2}"));
        }
        if let Some(c) = r.closest_m {
            line.push_str(&format!(", closest torsos {c:.2} m"));
        }
        if let Some(t) = r.first_touch_s {
            line.push_str(&format!(", first touch at {t:.2} s"));
        }
        let moved: Vec<String> = r
            .robots
            .iter()
            .map(|m| {
                let side = if m.ours { "our" } else { "their" };
                let falls = match m.falls {
                    0 => String::new(),
                    1 => " (1 fall)".to_string(),
                    n => format!(" ({n} falls)"),
                };
                format!("{side} {} {:.1} m{falls}", m.unum, m.distance_m())
            })
            .collect();
        if !moved.is_empty() {
            line.push_str(&format!(", moved: {}", moved.join(", ")));
        }
        line
    }

    /// Figures, one per line, then one line per run.
    pub fn render_text(&self) -> String {
        let mut out = String::new();
        let pct = 100.0 * self.success_rate();
        out.push_str(&format!("scenario: {} ({})\n", self.scenario, self.file));
        out.push_str(&format!("success condition: {}\n", self.condition));
        out.push_str(&format!("seed: {}\n", self.seed));
        out.push_str(&format!(
            "success: {}/{} ({pct:.0} %)\n",
            self.successes(),
            self.runs.len()
        ));
        let fmt = |t: Option<f64>| t.map_or_else(|| "-".into(), |t| format!("{t:.2} s"));
        out.push_str(&format!(
            "median time to success: {}\n",
            fmt(self.median_time_s())
        ));
        out.push_str(&format!(
            "mean time to success: {}\n",
            fmt(self.mean_time_s())
        ));
        let never = |t: Option<f64>| {
            t.map_or_else(
                || "never (half the runs or more)".into(),
                |t| format!("{t:.2} s"),
            )
        };
        out.push_str(&format!(
            "median time over all runs (a failure counts as never): {}\n",
            never(self.median_time_all_runs_s())
        ));
        out.push_str(&format!(
            "median time to our first touch of the ball: {}\n",
            never(self.median_first_touch_s())
        ));
        out.push_str(&format!("wall time: {:.1} s\n", self.wall_s));
        for r in &self.runs {
            out.push_str(&Self::run_line(r));
            out.push('\n');
        }
        out
    }

    pub fn render_json(&self) -> String {
        let per_run = self
            .runs
            .iter()
            .map(|r| JsonRun {
                index: r.index,
                success: r.success,
                time_s: r.time_s,
                why: r.why.clone(),
                ended: r.ended.clone(),
                ball: r.setup.ball,
                launch_velocity: r.setup.ball_velocity,
                launch_speed_m_s: r.setup.launch_speed(),
                launch_direction_deg: r.setup.launch_direction_deg(),
                target: r.setup.target,
                measured_launch: r.launch,
                ball_travel_m: r.ball_travel_m,
                goal_line_y: r.goal_line_y,
                ball_end: r.ball_end,
                goals_for: r.goals_for,
                goals_against: r.goals_against,
                closest_m: r.closest_m,
                first_touch_s: r.first_touch_s,
                robots: r.robots.clone(),
                ours: placements(&r.setup.ours),
                theirs: placements(&r.setup.theirs),
            })
            .collect();
        let doc = JsonSummary {
            scenario: &self.scenario,
            file: &self.file,
            success_condition: &self.condition,
            seed: self.seed,
            runs: self.runs.len(),
            successes: self.successes(),
            success_rate: self.success_rate(),
            median_time_s: self.median_time_s(),
            median_time_all_runs_s: self.median_time_all_runs_s(),
            median_first_touch_s: self.median_first_touch_s(),
            mean_time_s: self.mean_time_s(),
            wall_s: self.wall_s,
            per_run,
        };
        serde_json::to_string_pretty(&doc).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }
}

#[cfg(test)]
mod fall_tests {
    use super::FallCounter;

    #[test]
    fn a_fall_counts_once_until_the_robot_stands_again() {
        let mut c = FallCounter::new(2);
        for z in [0.6, 0.4, 0.2, 0.1, 0.3, 0.45, 0.2, 0.6, 0.55, 0.3, 0.6] {
            c.observe(0, Some(z));
        }
        c.observe(1, None);
        assert_eq!((c.of(0), c.of(1)), (2, 0));
    }
}

#[cfg(test)]
mod median_tests {
    use super::median_with_never;

    #[test]
    fn a_run_that_never_got_there_counts_as_longer_than_any() {
        let m = |v: &[Option<f64>]| median_with_never(v.iter().copied());
        assert_eq!(m(&[Some(3.0), None, Some(1.0)]), Some(3.0));
        assert_eq!(m(&[Some(3.0), Some(5.0), None, Some(1.0)]), Some(4.0));
        assert_eq!(m(&[Some(3.0), None, None, Some(1.0)]), None);
        assert_eq!(m(&[]), None);
    }
}
