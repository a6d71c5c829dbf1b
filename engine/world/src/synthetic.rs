//! Test helper: percepts rendered from a known pose like rcssservermj renders them (polar
//! coordinates truncated to 0.01, field of view ±60°, accelerometer = gravity).

use libero_model::kinematics::Kinematics;
use libero_model::{FieldGeometry, RobotModel};
use libero_protocol::percept::{JointReading, Polar, Seen, Vision};
use libero_protocol::Percept;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

pub struct Scene<'a> {
    pub model: &'a RobotModel,
    pub field: &'a FieldGeometry,
    pub kinematics: Kinematics,
    pub angles: Vec<f64>,
}

fn truncate(v: f64) -> f64 {
    (v * 100.0).trunc() / 100.0
}

pub fn polar_of(camera_point: Vector3<f64>) -> Option<Polar> {
    let d = camera_point.norm();
    let az = camera_point.y.atan2(camera_point.x).to_degrees();
    let el = (camera_point.z / d).asin().to_degrees();
    (az.abs() <= 60.0 && el.abs() <= 60.0).then(|| Polar {
        distance: truncate(d),
        azimuth_deg: truncate(az),
        elevation_deg: truncate(el),
    })
}

impl<'a> Scene<'a> {
    pub fn new(model: &'a RobotModel, field: &'a FieldGeometry) -> Self {
        Self {
            model,
            field,
            kinematics: Kinematics::new(model),
            angles: vec![0.0; model.joints.len()],
        }
    }

    pub fn set(&mut self, joint: &str, deg: f64) {
        let id = self.model.joint_id(joint).unwrap();
        self.angles[id] = deg;
    }

    pub fn torso(
        x: f64,
        y: f64,
        z: f64,
        yaw_deg: f64,
        roll_deg: f64,
        pitch_deg: f64,
    ) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(x, y, z),
            UnitQuaternion::from_euler_angles(
                roll_deg.to_radians(),
                pitch_deg.to_radians(),
                yaw_deg.to_radians(),
            ),
        )
    }

    /// The camera pose in the field frame.
    pub fn camera(&self, torso: &Isometry3<f64>) -> Isometry3<f64> {
        torso * self.kinematics.frame_pose("camera", &self.angles).unwrap()
    }

    /// A percept at `time` with vision (when `with_vision`) of every landmark and of `ball`.
    pub fn percept(
        &self,
        torso: &Isometry3<f64>,
        time: f64,
        with_vision: bool,
        ball: Option<Vector3<f64>>,
    ) -> Percept<'a> {
        let camera = self.camera(torso);
        let to_camera = |p: Vector3<f64>| camera.inverse_transform_point(&p.into()).coords;
        let vision = with_vision.then(|| Vision {
            landmarks: self
                .field
                .landmarks
                .iter()
                .filter_map(|l| {
                    polar_of(to_camera(Vector3::from(l.position))).map(|at| Seen {
                        name: l.name.as_str(),
                        at,
                    })
                })
                .collect(),
            ball: ball.and_then(|b| polar_of(to_camera(b))),
            ..Default::default()
        });
        let gravity = torso.rotation.inverse() * Vector3::new(0.0, 0.0, 9.81);
        Percept {
            time: Some(time),
            gyro: Some([0.0; 3]),
            accel: Some(gravity.map(truncate).into()),
            joints: self
                .model
                .joints
                .iter()
                .zip(&self.angles)
                .map(|(j, a)| JointReading {
                    perceptor: j.perceptor.as_str(),
                    angle_deg: truncate(*a),
                    velocity_deg: Some(0.0),
                })
                .collect(),
            vision,
            ..Default::default()
        }
    }
}
