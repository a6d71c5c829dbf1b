//! Where the foot met the ball: the kicking foot's pose at the first cycle the ball moves,
//! from the measured joint angles (forward kinematics) and the server's torso and ball ground
//! truth. For measuring the kick's contact geometry, never for the agent's decisions.

use libero_model::kinematics::{BodyPoses, Kinematics};
use libero_model::RobotModel;
use libero_world::World;
use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion};

/// The kicking foot at the moment of contact, world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Which foot: the one whose toe was nearer the ball.
    pub left: bool,
    /// Yaw of the foot's long axis [deg].
    pub foot_yaw_deg: f64,
    /// Direction the toe was moving [deg].
    pub swing_deg: f64,
    /// Toe speed [m/s].
    pub toe_speed_m_s: f64,
    /// Ball centre relative to the toe face's centre, in the foot's frame: forward, left, up [m].
    pub ball_in_foot: [f64; 3],
    /// Torso yaw [deg].
    pub torso_yaw_deg: f64,
    /// Both feet in the torso frame when the kick motion began: x, y [m], yaw [deg].
    pub start_feet: [[f64; 3]; 2],
}

/// Follows both feet cycle by cycle and reports the contact once.
#[derive(Clone)]
pub struct ContactTracer {
    kin: Kinematics,
    poses: BodyPoses,
    feet: [usize; 2],
    /// The toe face centre in the foot frame [m].
    toe: Point3<f64>,
    last: Option<(f64, [Isometry3<f64>; 2])>,
    ball_rest: Option<[f64; 3]>,
    start_feet: Option<[[f64; 3]; 2]>,
    contact: Option<Contact>,
}

/// The ball has been touched once it is this far from where it lay [m].
const MOVED_M: f64 = 0.01;

impl ContactTracer {
    pub fn new(model: &RobotModel, toe_ahead_m: f64) -> Option<Self> {
        let kin = Kinematics::new(model);
        let feet = [kin.frame_id("left_foot")?, kin.frame_id("right_foot")?];
        Some(Self {
            poses: kin.new_poses(),
            kin,
            feet,
            // The T1 foot box is 3 cm thick below the ankle-roll frame.
            toe: Point3::new(toe_ahead_m, 0.0, -0.015),
            last: None,
            ball_rest: None,
            start_feet: None,
            contact: None,
        })
    }

    pub fn contact(&self) -> Option<Contact> {
        self.contact
    }

    /// One cycle while the kick motion runs; `ball`: ground truth.
    pub fn observe(&mut self, world: &World, ball: Option<[f64; 3]>) {
        if self.contact.is_some() {
            return;
        }
        let (Some(p), Some(q), Some(ball)) = (
            world.truth.torso_position,
            world.truth.torso_orientation,
            ball,
        ) else {
            return;
        };
        if self
            .kin
            .forward(&world.body.joint_angles, &mut self.poses)
            .is_err()
        {
            return;
        }
        let torso = Isometry3::from_parts(
            Translation3::new(p[0], p[1], p[2]),
            UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3])),
        );
        let (Some(l), Some(r)) = (
            self.poses.frame_in_torso(self.feet[0]),
            self.poses.frame_in_torso(self.feet[1]),
        ) else {
            return;
        };
        let planar = |f: &Isometry3<f64>| {
            let a = f.rotation * nalgebra::Vector3::x();
            [
                f.translation.x,
                f.translation.y,
                a.y.atan2(a.x).to_degrees(),
            ]
        };
        let start_feet = *self.start_feet.get_or_insert([planar(l), planar(r)]);
        let feet = [torso * l, torso * r];
        if log::log_enabled!(log::Level::Trace) {
            let axis = torso.rotation * nalgebra::Vector3::x();
            let yaw = |f: &Isometry3<f64>| {
                let a = f.rotation * nalgebra::Vector3::x();
                a.y.atan2(a.x).to_degrees()
            };
            log::trace!(
                "t {:.2} torso yaw {:.1} (estimate {:.1}) feet yaw {:.1} {:.1} feet {:.3?} {:.3?} ball {:.3?} gyro z {:.0}",
                world.time,
                axis.y.atan2(axis.x).to_degrees(),
                world.me.yaw_deg,
                yaw(&feet[0]),
                yaw(&feet[1]),
                feet[0].translation.vector.as_slice(),
                feet[1].translation.vector.as_slice(),
                ball,
                world.body.gyro[2]
            );
        }
        let rest = *self.ball_rest.get_or_insert(ball);
        let moved = (ball[0] - rest[0]).hypot(ball[1] - rest[1]) > MOVED_M;
        if moved {
            if let Some((t, before)) = self.last {
                let ball_point = Point3::new(rest[0], rest[1], rest[2]);
                let toe = |f: &Isometry3<f64>| f * self.toe;
                let k = if (toe(&before[0]) - ball_point).norm()
                    <= (toe(&before[1]) - ball_point).norm()
                {
                    0
                } else {
                    1
                };
                let foot = before[k];
                let axis = foot.rotation * nalgebra::Vector3::x();
                let swing = toe(&feet[k]) - toe(&before[k]);
                let dt = (world.time - t).max(1e-3);
                let local = foot.inverse() * ball_point - self.toe.coords;
                let torso_axis = torso.rotation * nalgebra::Vector3::x();
                self.contact = Some(Contact {
                    left: k == 0,
                    foot_yaw_deg: axis.y.atan2(axis.x).to_degrees(),
                    swing_deg: swing.y.atan2(swing.x).to_degrees(),
                    toe_speed_m_s: swing.norm() / dt,
                    ball_in_foot: [local.x, local.y, local.z],
                    torso_yaw_deg: torso_axis.y.atan2(torso_axis.x).to_degrees(),
                    start_feet,
                });
            }
        }
        self.last = Some((world.time, feet));
    }
}
