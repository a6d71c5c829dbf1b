//! The match report's figures, counted from the server's ground truth (evaluation only: the
//! agents never see any of it). The runner feeds one [`Sample`] per monitor update.

use serde::Serialize;
use std::collections::HashMap;

/// A robot is down once its torso is below this share of its standing height, and up again
/// above this one (the T1's 0.30 m and 0.50 m of 0.67 m; a NAO's 0.17 m and 0.29 m of
/// 0.385 m, its walk crouching at ~0.35 m).
const DOWN_BELOW_SHARE: f64 = 0.45;
const UP_ABOVE_SHARE: f64 = 0.75;

/// Torso heights [m] that count a robot down and up again.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DownAndUp {
    pub down_below_m: f64,
    pub up_above_m: f64,
}

impl DownAndUp {
    /// For robots standing `standing_m` tall (the lowest of a match's models: fixed T1
    /// heights read every NAO that fell as down until the end of the half).
    pub fn of_standing(standing_m: f64) -> Self {
        Self {
            down_below_m: standing_m * DOWN_BELOW_SHARE,
            up_above_m: standing_m * UP_ABOVE_SHARE,
        }
    }
}
/// A fall the robot has not got up from within this long breaks the match bar.
pub const STAND_WITHIN_S: f64 = 8.0;
/// A robot whose torso jumps this far between two updates outside the beam modes was moved by
/// the referee.
const RELOCATION_M: f64 = 1.0;
/// Ball speeds [m/s] that start a launch (a kick or a hard push) and end it.
const LAUNCH_M_S: f64 = 1.5;
const REARM_M_S: f64 = 0.5;
/// A launch belongs to the robot nearest the ball within this distance [m].
const KICKER_WITHIN_M: f64 = 1.0;
/// A launch is a shot when it heads for the goal line within this margin of the mouth [m] from
/// no further out than `SHOT_RANGE_M`.
const SHOT_MARGIN_M: f64 = 2.0;
const SHOT_RANGE_M: f64 = 20.0;
/// The ball is held by the nearest robot within this distance [m]; a pass is completed when a
/// teammate holds it next after it travelled at least `PASS_MIN_M`.
const HOLD_WITHIN_M: f64 = 0.5;
const PASS_MIN_M: f64 = 2.0;
/// Possession: the side whose nearest robot is nearer the ball, when within this distance [m].
const POSSESSION_WITHIN_M: f64 = 1.0;

/// One robot in one update.
#[derive(Clone, Debug)]
pub struct RobotSample {
    pub left: bool,
    pub unum: u32,
    /// Torso position, ground truth [m].
    pub torso: [f64; 3],
    /// The agent's own estimate of its ground position.
    pub estimate: Option<[f64; 2]>,
}

/// One monitor update. Robots are only those the runner can see (its own agents).
#[derive(Clone, Debug)]
pub struct Sample {
    /// Play time [s].
    pub time: f64,
    pub mode: String,
    pub ball: [f64; 3],
    pub score: (u32, u32),
    pub robots: Vec<RobotSample>,
}

/// The field's numbers the figures need.
#[derive(Clone, Copy, Debug)]
pub struct Goals {
    pub half_length: f64,
    pub goal_half_width: f64,
}

/// One side's figures over a half (or a match, once added up).
#[derive(Clone, Debug, Default, Serialize)]
pub struct Figures {
    pub goals: u32,
    pub shots: u32,
    pub shots_on_target: u32,
    /// Seconds of play-on in which this side had the ball (`POSSESSION_WITHIN_M`).
    pub possession_s: f64,
    pub passes_completed: u32,
    pub falls: u32,
    /// Falls not followed by standing again within `STAND_WITHIN_S`.
    pub falls_slow_to_stand: u32,
    /// Those falls: (uniform number, play time of the fall [s], time down [s]).
    pub slow_falls: Vec<(u32, f64, f64)>,
    /// The longest time any robot lay down [s].
    pub longest_down_s: f64,
    /// The largest share of the play time any one robot spent down.
    pub most_down_share: f64,
    /// Robots moved by the referee (a rule breach, or lying too long).
    pub relocations: u32,
    /// The fouls the referee called (SimSpark reports them; rcssservermj does not): counts by
    /// player and kind, and the most recent with their play time.
    pub fouls: Vec<FoulCount>,
    pub recent_fouls: Vec<FoulAt>,
    /// Mean distance between the agents' self-estimates and the truth during play-on [m].
    pub localization_error_m: Option<f64>,
    /// Seconds from each own kick-off's start to the first touch (play on).
    pub kick_off_times_s: Vec<f64>,
    pub missed_cycles: u64,
    /// Whether the robots of this side were seen (an external team's are not: its
    /// robot-based figures are zero).
    pub observed: bool,
    #[serde(skip)]
    localization_sum: f64,
    #[serde(skip)]
    localization_n: u64,
}

impl Figures {
    /// Add another half's figures (the sides' names already matched).
    pub fn add(&mut self, other: &Figures) {
        self.goals += other.goals;
        self.shots += other.shots;
        self.shots_on_target += other.shots_on_target;
        self.possession_s += other.possession_s;
        self.passes_completed += other.passes_completed;
        self.falls += other.falls;
        self.falls_slow_to_stand += other.falls_slow_to_stand;
        self.slow_falls.extend_from_slice(&other.slow_falls);
        self.longest_down_s = self.longest_down_s.max(other.longest_down_s);
        self.most_down_share = self.most_down_share.max(other.most_down_share);
        self.relocations += other.relocations;
        for foul in &other.fouls {
            match self
                .fouls
                .iter_mut()
                .find(|f| f.unum == foul.unum && f.kind == foul.kind)
            {
                Some(f) => f.count += foul.count,
                None => self.fouls.push(foul.clone()),
            }
        }
        self.fouls
            .sort_by(|a, b| (a.unum, &a.kind).cmp(&(b.unum, &b.kind)));
        self.recent_fouls.extend_from_slice(&other.recent_fouls);
        self.kick_off_times_s
            .extend_from_slice(&other.kick_off_times_s);
        self.missed_cycles += other.missed_cycles;
        self.observed |= other.observed;
        self.localization_sum += other.localization_sum;
        self.localization_n += other.localization_n;
        self.localization_error_m =
            (self.localization_n > 0).then(|| self.localization_sum / self.localization_n as f64);
    }
}

/// How often the referee called one kind of foul on one player.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FoulCount {
    pub unum: u32,
    pub kind: String,
    pub count: u32,
}

/// One foul: when, on whom, what.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FoulAt {
    pub time_s: f64,
    pub unum: u32,
    pub kind: String,
}

impl Figures {
    /// The fouls the server's referee called on this side (`left`) so far.
    pub fn set_fouls(&mut self, tally: &libero_server::FoulTally, left: bool) {
        self.fouls = tally
            .counts(left)
            .into_iter()
            .map(|(unum, kind, count)| FoulCount {
                unum,
                kind: kind.to_string(),
                count,
            })
            .collect();
        self.recent_fouls = tally
            .recent(left)
            .map(|f| FoulAt {
                time_s: f.time,
                unum: f.unum,
                kind: f.kind.to_string(),
            })
            .collect();
    }
}

#[derive(Debug, Default)]
struct RobotTrack {
    down_since: Option<f64>,
    down_s: f64,
    last: Option<[f64; 2]>,
}

/// Counts one half.
#[derive(Debug)]
pub struct Observer {
    goals: Goals,
    posture: DownAndUp,
    last: Option<Sample>,
    robots: HashMap<(bool, u32), RobotTrack>,
    /// Figures by side: `[left, right]`.
    sides: [Figures; 2],
    play_on_s: f64,
    launch_armed: bool,
    /// The holder: side, number, and the ball where it last held it.
    holder: Option<(bool, u32, [f64; 2])>,
    /// An own kick-off in progress: the kicking side and its start.
    kick_off: Option<(bool, f64)>,
    /// Play time of the last beam mode (a jump just after one is a beam, not the referee).
    last_beam_mode_at: f64,
}

fn index(left: bool) -> usize {
    usize::from(!left)
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn beam_mode(mode: &str) -> bool {
    mode == "BeforeKickOff" || mode.starts_with("Goal_")
}

impl Observer {
    pub fn new(goals: Goals, posture: DownAndUp) -> Self {
        Self {
            goals,
            posture,
            last: None,
            robots: HashMap::new(),
            sides: Default::default(),
            play_on_s: 0.0,
            launch_armed: true,
            holder: None,
            kick_off: None,
            last_beam_mode_at: f64::NEG_INFINITY,
        }
    }

    pub fn feed(&mut self, sample: Sample) {
        let Some(last) = self.last.take() else {
            self.last = Some(sample);
            return;
        };
        let dt = sample.time - last.time;
        if beam_mode(&sample.mode) || beam_mode(&last.mode) {
            self.last_beam_mode_at = sample.time;
        }
        self.count_goals(&last, &sample);
        self.count_kick_offs(&last, &sample);
        for robot in &sample.robots {
            self.sides[index(robot.left)].observed = true;
            self.track_robot(robot, &sample, dt);
        }
        if sample.mode == "PlayOn" && dt > 0.0 {
            self.play_on_s += dt;
            self.count_possession(&sample, dt);
            self.count_localization(&sample);
        }
        self.count_launch(&last, &sample, dt);
        self.count_holds(&sample);
        self.last = Some(sample);
    }

    fn count_goals(&mut self, last: &Sample, now: &Sample) {
        self.sides[0].goals += now.score.0.saturating_sub(last.score.0);
        self.sides[1].goals += now.score.1.saturating_sub(last.score.1);
    }

    fn count_kick_offs(&mut self, last: &Sample, now: &Sample) {
        if now.mode != last.mode {
            match now.mode.as_str() {
                "KickOff_Left" => self.kick_off = Some((true, now.time)),
                "KickOff_Right" => self.kick_off = Some((false, now.time)),
                "PlayOn" => {
                    if let Some((left, start)) = self.kick_off.take() {
                        self.sides[index(left)]
                            .kick_off_times_s
                            .push(now.time - start);
                    }
                }
                _ => self.kick_off = None,
            }
        }
    }

    fn track_robot(&mut self, robot: &RobotSample, now: &Sample, dt: f64) {
        let figures = &mut self.sides[index(robot.left)];
        let track = self.robots.entry((robot.left, robot.unum)).or_default();
        let at = [robot.torso[0], robot.torso[1]];
        let settled = now.time - self.last_beam_mode_at > 0.2;
        if let Some(last) = track.last {
            if settled && dt <= 0.2 && distance(last, at) > RELOCATION_M {
                figures.relocations += 1;
                log::info!(
                    "t {:.2} ({}): {} {} moved by the referee from ({:.2}, {:.2}) to ({:.2}, {:.2})",
                    now.time,
                    now.mode,
                    if robot.left { "left" } else { "right" },
                    robot.unum,
                    last[0],
                    last[1],
                    at[0],
                    at[1]
                );
            }
        }
        track.last = Some(at);
        let counted = now.mode != "BeforeKickOff";
        match track.down_since {
            None if robot.torso[2] < self.posture.down_below_m && counted => {
                track.down_since = Some(now.time);
                figures.falls += 1;
            }
            Some(since) => {
                if dt > 0.0 {
                    track.down_s += dt;
                }
                let down_for = now.time - since;
                if robot.torso[2] > self.posture.up_above_m || !counted {
                    track.down_since = None;
                    if down_for > STAND_WITHIN_S {
                        figures.falls_slow_to_stand += 1;
                        figures.slow_falls.push((robot.unum, since, down_for));
                    }
                }
                figures.longest_down_s = figures.longest_down_s.max(down_for);
            }
            None => {}
        }
    }

    fn nearest(&self, sample: &Sample, left: bool) -> Option<(u32, f64)> {
        let ball = [sample.ball[0], sample.ball[1]];
        sample
            .robots
            .iter()
            .filter(|r| r.left == left)
            .map(|r| (r.unum, distance(ball, [r.torso[0], r.torso[1]])))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

    fn count_possession(&mut self, sample: &Sample, dt: f64) {
        let near = [self.nearest(sample, true), self.nearest(sample, false)];
        for side in 0..2 {
            let Some((_, d)) = near[side] else { continue };
            let other = near[1 - side].map_or(f64::INFINITY, |o| o.1);
            if d <= POSSESSION_WITHIN_M && d < other {
                self.sides[side].possession_s += dt;
            }
        }
    }

    fn count_localization(&mut self, sample: &Sample) {
        for robot in &sample.robots {
            if let Some(estimate) = robot.estimate {
                let figures = &mut self.sides[index(robot.left)];
                figures.localization_sum += distance(estimate, [robot.torso[0], robot.torso[1]]);
                figures.localization_n += 1;
            }
        }
    }

    fn count_launch(&mut self, last: &Sample, now: &Sample, dt: f64) {
        if !(dt > 0.0 && dt <= 0.25) || now.mode != "PlayOn" && last.mode != "PlayOn" {
            return;
        }
        let v = [
            (now.ball[0] - last.ball[0]) / dt,
            (now.ball[1] - last.ball[1]) / dt,
        ];
        let speed = v[0].hypot(v[1]);
        if speed < REARM_M_S {
            self.launch_armed = true;
        }
        if !self.launch_armed || speed < LAUNCH_M_S {
            return;
        }
        self.launch_armed = false;
        let Some(left) = self.kicker_side(last) else {
            return;
        };
        // The left team attacks the goal at +x.
        let goal_x = if left {
            self.goals.half_length
        } else {
            -self.goals.half_length
        };
        let (bx, by) = (last.ball[0], last.ball[1]);
        let towards = (goal_x - bx) * v[0];
        if towards <= 0.0 || (goal_x - bx).abs() > SHOT_RANGE_M {
            return;
        }
        let crossing = by + v[1] * (goal_x - bx) / v[0];
        let figures = &mut self.sides[index(left)];
        if crossing.abs() <= self.goals.goal_half_width + SHOT_MARGIN_M {
            figures.shots += 1;
            if crossing.abs() <= self.goals.goal_half_width {
                figures.shots_on_target += 1;
            }
        }
    }

    /// The side of the robot nearest the ball, when one is near enough; an unobserved side
    /// when no observed robot is.
    fn kicker_side(&self, sample: &Sample) -> Option<bool> {
        let near = [self.nearest(sample, true), self.nearest(sample, false)];
        let best = (0..2)
            .filter_map(|s| near[s].map(|n| (s, n.1)))
            .filter(|(_, d)| *d <= KICKER_WITHIN_M)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match best {
            Some((side, _)) => Some(side == 0),
            None => {
                let unobserved: Vec<usize> = (0..2).filter(|s| !self.sides[*s].observed).collect();
                (unobserved.len() == 1).then(|| unobserved[0] == 0)
            }
        }
    }

    fn count_holds(&mut self, sample: &Sample) {
        if sample.mode != "PlayOn" {
            self.holder = None;
            return;
        }
        let ball = [sample.ball[0], sample.ball[1]];
        let Some(robot) = sample
            .robots
            .iter()
            .filter(|r| distance(ball, [r.torso[0], r.torso[1]]) <= HOLD_WITHIN_M)
            .min_by(|a, b| {
                distance(ball, [a.torso[0], a.torso[1]])
                    .total_cmp(&distance(ball, [b.torso[0], b.torso[1]]))
            })
        else {
            return;
        };
        if let Some((left, unum, held_at)) = self.holder {
            if left == robot.left && unum != robot.unum && distance(held_at, ball) >= PASS_MIN_M {
                self.sides[index(left)].passes_completed += 1;
            }
        }
        self.holder = Some((robot.left, robot.unum, ball));
    }

    /// The half's figures, `[left, right]`, and its play-on time [s].
    pub fn finish(mut self, play_time_s: f64) -> ([Figures; 2], f64) {
        for ((left, unum), track) in &self.robots {
            let figures = &mut self.sides[index(*left)];
            if let (Some(since), Some(last)) = (track.down_since, &self.last) {
                if last.time - since > STAND_WITHIN_S {
                    figures.falls_slow_to_stand += 1;
                    figures.slow_falls.push((*unum, since, last.time - since));
                }
            }
            if play_time_s > 0.0 {
                figures.most_down_share = figures.most_down_share.max(track.down_s / play_time_s);
            }
        }
        for figures in &mut self.sides {
            figures.localization_error_m = (figures.localization_n > 0)
                .then(|| figures.localization_sum / figures.localization_n as f64);
        }
        (self.sides, self.play_on_s)
    }
}

#[cfg(test)]
mod tests;
