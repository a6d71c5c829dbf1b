//! World-model accuracy against the real rcssservermj (fast `--sync --no-realtime` mode).
//!
//! * Localization: a T1 standing at 20 places across the 7v7 field, panning its head ±60°;
//!   every vision frame's estimate is compared with the server's ground truth.
//! * Ball: 20 launches through the monitor (1–8 m/s, directions all round); the stop point
//!   predicted after the first 0.3 s of observed motion is compared with where the ball stops.
//!
//! The ground truth is read only here, to score the estimates; the world model never sees it.
//! The ball's true position comes from the true torso pose, the joint angles and the (noise-free)
//! ball observation, since the server does not send the ball's position to agents.

use libero_model::kinematics::Kinematics;
use libero_model::RobotModel;
use libero_protocol::action::MotorCommand;
use libero_protocol::frame::FrameReader;
use libero_protocol::{parse_percept, ActionWriter, Percept};
use libero_server::Monitor;
use libero_world::geometry::{heading_deg_of_quaternion, polar_to_point, wrap_deg};
use libero_world::World;
use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector2, Vector3};
use std::io::Write;
use std::net::TcpStream;
use std::time::{Duration, Instant};

const TEAM: &str = "WorldLive";
const UNUM: u32 = 1;
/// T1 torso height with the soles on the ground (rcssservermj.md §3.2).
const T1_HEIGHT: f64 = 0.6735;

/// A T1 holding the stand pose with a commanded head, its world model updated every cycle.
struct Agent {
    reader: FrameReader<TcpStream>,
    stream: TcpStream,
    model: RobotModel,
    kinematics: Kinematics,
    writer: ActionWriter,
    out: Vec<u8>,
    world: World,
}

/// What the test keeps of one cycle.
struct Cycle {
    has_vision: bool,
    true_torso: Option<Isometry3<f64>>,
    /// Ball in the field frame from the true pose (only when seen).
    true_ball: Option<Vector3<f64>>,
}

impl Agent {
    fn connect(port: u16) -> Agent {
        let model = RobotModel::builtin("T1").unwrap();
        let stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
        stream.set_nodelay(true).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_secs(20)))
            .unwrap();
        let mut writer = ActionWriter::new(model.server);
        writer.init(&model, TEAM, UNUM).unwrap();
        let mut out = Vec::new();
        writer.frame_into(&mut out);
        let mut stream_w = stream.try_clone().unwrap();
        stream_w.write_all(&out).unwrap();
        Agent {
            reader: FrameReader::with_limit(stream.try_clone().unwrap(), 1 << 20),
            stream: stream_w,
            kinematics: Kinematics::new(&model),
            world: World::new(&model, TEAM, UNUM),
            model,
            writer,
            out,
        }
    }

    /// Read one percept, update the world, answer with the stand pose and this head angle.
    fn step(&mut self, head_yaw: f64, head_pitch: f64) -> Cycle {
        let payload = self.reader.read_frame().expect("percept").to_vec();
        let percept = parse_percept(&payload, self.model.server).expect("readable percept");
        self.world.update(&self.model, &percept);
        let cycle = self.observe_truth(&percept);
        self.answer(head_yaw, head_pitch);
        cycle
    }

    fn observe_truth(&self, percept: &Percept<'_>) -> Cycle {
        let true_torso = percept
            .truth_position
            .zip(percept.truth_orientation)
            .map(|(p, q)| {
                Isometry3::from_parts(
                    Translation3::new(p[0], p[1], p[2]),
                    UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3])),
                )
            });
        let camera = self
            .kinematics
            .frame_pose("camera", &self.world.body.joint_angles)
            .unwrap();
        let true_ball = percept
            .vision
            .as_ref()
            .and_then(|v| v.ball.as_ref())
            .and_then(polar_to_point)
            .zip(true_torso)
            .map(|(p, torso)| (torso * camera * p).coords);
        Cycle {
            has_vision: percept.vision.is_some(),
            true_torso,
            true_ball,
        }
    }

    fn answer(&mut self, head_yaw: f64, head_pitch: f64) {
        let pose = [
            ("left_hip_pitch", -12.0),
            ("right_hip_pitch", -12.0),
            ("left_knee", 24.0),
            ("right_knee", 24.0),
            ("left_ankle_pitch", -12.0),
            ("right_ankle_pitch", -12.0),
            ("left_shoulder_roll", -80.0),
            ("right_shoulder_roll", 80.0),
            ("left_elbow_yaw", -23.0),
            ("right_elbow_yaw", 23.0),
            ("head_yaw", head_yaw),
            ("head_pitch", head_pitch),
        ];
        self.writer.clear();
        for joint in &self.model.joints {
            let target = pose
                .iter()
                .find(|(name, _)| *name == joint.name)
                .map_or(0.0, |(_, q)| *q);
            self.writer.motor(
                joint,
                MotorCommand {
                    q_deg: target,
                    dq_deg: 0.0,
                    kp: joint.gains.kp,
                    kd: joint.gains.kd,
                    tau: 0.0,
                },
            );
        }
        self.out.clear();
        self.writer.frame_into(&mut self.out);
        self.stream.write_all(&self.out).unwrap();
    }
}

/// A server and our agent. Use the server's own monitor connection (`server.monitor()`):
/// rcsssmj 0.2.1 can crash when a monitor disconnects while it runs.
fn start() -> (libero_tests::LiveServer, Agent) {
    let server = libero_tests::fast_server();
    let agent = Agent::connect(server.agent_port);
    (server, agent)
}

fn move_agent(monitor: &mut Monitor, x: f64, y: f64, yaw_deg: f64) {
    monitor
        .send(&format!(
            "(agent (unum {UNUM}) (team Left) (move {x} {y} {T1_HEIGHT} {yaw_deg}))"
        ))
        .unwrap();
}

/// Move the agent and step until the server's ground truth has it there, sending the move again
/// if it was ignored: right after the agent connects, rcsssmj can drop a monitor move (the robot
/// then stays at its spawn point outside the field).
fn place_agent(agent: &mut Agent, monitor: &mut Monitor, x: f64, y: f64, yaw_deg: f64) {
    for attempt in 0..200 {
        if attempt % 20 == 0 {
            if attempt > 0 {
                eprintln!("the move to ({x:.2}, {y:.2}) was ignored: sending it again");
            }
            move_agent(monitor, x, y, yaw_deg);
        }
        let cycle = agent.step(0.0, 20.0);
        let placed = cycle
            .true_torso
            .is_some_and(|p| (p.translation.vector.xy() - Vector2::new(x, y)).norm() < 0.1);
        if placed {
            return;
        }
    }
    panic!("the agent could not be moved to ({x}, {y})");
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i]
}

#[test]
fn localization_standing_at_20_places_with_head_panning() {
    let wall = Instant::now();
    let (mut server, mut agent) = start();
    let monitor = server.monitor();
    let mut position_errors = Vec::new();
    let mut yaw_errors = Vec::new();
    let mut places = Vec::new();
    for (i, x) in [-22.0, -11.0, 0.0, 11.0, 22.0].into_iter().enumerate() {
        for (j, y) in [-12.0, -4.0, 4.0, 12.0].into_iter().enumerate() {
            let yaw = wrap_deg(((i * 4 + j) as f64) * 73.0);
            places.push((x, y, yaw));
        }
    }
    for &(x, y, yaw) in &places {
        move_agent(monitor, x, y, yaw);
        let mut place_errors = Vec::new();
        // 1 s to settle after the move, then 2 s of measurement (one head period).
        for k in 0..150 {
            let t = k as f64 * 0.02;
            let head_yaw = 60.0 * (std::f64::consts::TAU * t / 2.0).sin();
            let cycle = agent.step(head_yaw, 20.0);
            if k < 50 || !cycle.has_vision {
                continue;
            }
            let truth = cycle.true_torso.expect("rcssservermj sends ground truth");
            let me = &agent.world.me;
            assert!(me.localized, "not localized at ({x}, {y})");
            let error = (Vector2::from(me.position) - truth.translation.vector.xy()).norm();
            let q = truth.rotation.quaternion();
            let true_yaw = heading_deg_of_quaternion([q.w, q.i, q.j, q.k]);
            position_errors.push(error);
            yaw_errors.push(wrap_deg(me.yaw_deg - true_yaw).abs());
            place_errors.push(error);
        }
        let worst = place_errors.iter().cloned().fold(0.0, f64::max);
        eprintln!(
            "place ({x:6.1}, {y:6.1}, {yaw:7.1}°): worst position error {:.3} m, posture {:?}",
            worst, agent.world.body.posture
        );
    }
    position_errors.sort_by(f64::total_cmp);
    yaw_errors.sort_by(f64::total_cmp);
    let (median, p95) = (
        percentile(&position_errors, 0.5),
        percentile(&position_errors, 0.95),
    );
    let yaw_median = percentile(&yaw_errors, 0.5);
    eprintln!(
        "localization over {} vision frames: position median {:.4} m, p95 {:.4} m, max {:.4} m; \
         yaw median {:.3}°, p95 {:.3}°; {:.1} s wall",
        position_errors.len(),
        median,
        p95,
        position_errors.last().unwrap(),
        yaw_median,
        percentile(&yaw_errors, 0.95),
        wall.elapsed().as_secs_f64()
    );
    assert!(position_errors.len() >= 20 * 45);
    assert!(median <= 0.03, "position median {median}");
    assert!(p95 <= 0.08, "position p95 {p95}");
    assert!(yaw_median <= 1.0, "yaw median {yaw_median}");
}

#[test]
fn ball_stop_point_predicted_from_the_first_third_of_a_second() {
    let wall = Instant::now();
    let (mut server, mut agent) = start();
    let monitor = server.monitor();
    let mut worst_relative: f64 = 0.0;
    let mut relative_errors = Vec::new();
    for k in 0..20 {
        let speed = 1.0 + 7.0 * k as f64 / 19.0;
        let heading = (k as f64 * 137.5f64).to_radians();
        let dir = Vector2::new(heading.cos(), heading.sin());
        let start = -8.0 * dir;
        let robot = start - 2.0 * dir;
        place_agent(&mut agent, monitor, robot.x, robot.y, heading.to_degrees());
        monitor
            .send(&format!(
                "(ball (pos {} {} 0.11)(vel 0 0 0))",
                start.x, start.y
            ))
            .unwrap();
        // Settle and watch the ball lie still. The first move brings the robot from its spawn
        // point outside the field, so its self-estimate needs longer to settle there.
        let settle_cycles = if k == 0 { 150 } else { 60 };
        for _ in 0..settle_cycles {
            agent.step(0.0, 20.0);
        }
        let v = dir * speed;
        monitor
            .send(&format!(
                "(ball (pos {} {} 0.11)(vel {} {} 0))",
                start.x, start.y, v.x, v.y
            ))
            .unwrap();
        let mut first_motion: Option<f64> = None;
        let mut predicted: Option<Vector2<f64>> = None;
        let mut last_true: Option<(f64, Vector2<f64>)> = None;
        let mut still_since: Option<f64> = None;
        for _ in 0..600 {
            let cycle = agent.step(0.0, 20.0);
            let now = agent.world.time;
            let Some(ball) = cycle.true_ball.map(|b| b.xy()) else {
                continue;
            };
            if first_motion.is_none() && (ball - start).norm() > 0.02 {
                first_motion = Some(now);
            }
            // The prediction after 0.28 s of observed motion: 8 frames, the ball having moved
            // for at most 0.32 s (it started between the previous frame and the first one).
            if let (Some(t0), None) = (first_motion, predicted) {
                if now - t0 >= 0.28 - 1e-6 {
                    predicted = Some(Vector2::from(agent.world.ball.predicted_stop));
                }
            }
            if let Some((_, before)) = last_true {
                if (ball - before).norm() < 0.002 && first_motion.is_some() {
                    let since = *still_since.get_or_insert(now);
                    if now - since >= 0.4 {
                        break;
                    }
                } else {
                    still_since = None;
                }
            }
            last_true = Some((now, ball));
        }
        let stop = last_true.expect("the ball was seen").1;
        let predicted = predicted.expect("prediction made");
        let roll = (stop - start).norm();
        let error = (predicted - stop).norm();
        let relative = error / roll;
        // The error split along the launch direction and to its left.
        let off = predicted - stop;
        eprintln!(
            "launch {k:2}: {speed:.2} m/s at {:6.1}°: rolled {roll:6.3} m, predicted stop off by \
             {error:.3} m ({:.1} %; along {:+.3}, left {:+.3}), drag factor {:.3}",
            heading.to_degrees() % 360.0,
            100.0 * relative,
            off.dot(&dir),
            off.perp(&dir),
            agent.world.ball.drag_factor
        );
        relative_errors.push(relative);
        worst_relative = worst_relative.max(relative);
    }
    relative_errors.sort_by(f64::total_cmp);
    eprintln!(
        "ball stop point: median {:.1} %, worst {:.1} % of the roll distance; {:.1} s wall",
        100.0 * percentile(&relative_errors, 0.5),
        100.0 * worst_relative,
        wall.elapsed().as_secs_f64()
    );
    assert!(
        worst_relative <= 0.10,
        "worst stop-point error {:.1} % of the roll distance",
        100.0 * worst_relative
    );
}
