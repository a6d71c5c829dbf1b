//! Points in the three planar frames the agent reasons in, as distinct types so they cannot be
//! mixed by accident (the HULKs `coordinate_systems` pattern):
//!
//! - [`Global`]: the server's field frame — origin at the centre spot, +x towards the right goal.
//! - [`Own`]: the team's own frame — own goal at −x, whichever side the team plays on. Trees,
//!   formations and strategy files speak this frame.
//! - [`Robot`]: the robot's frame — x forwards, y left, origin under the torso.
//!
//! Conversions are explicit and live here only: [`TeamSide`] turns global into own and back, a
//! [`Pose`] (the robot's global position and heading) turns global into robot and back.

use crate::game::Side;
use std::ops::{Add, Sub};

macro_rules! planar_point {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Default)]
        pub struct $name {
            pub x: f64,
            pub y: f64,
        }

        impl $name {
            pub const fn new(x: f64, y: f64) -> Self {
                Self { x, y }
            }
            pub fn from_array([x, y]: [f64; 2]) -> Self {
                Self { x, y }
            }
            pub fn to_array(self) -> [f64; 2] {
                [self.x, self.y]
            }
            pub fn distance(self, other: Self) -> f64 {
                (self.x - other.x).hypot(self.y - other.y)
            }
            pub fn norm(self) -> f64 {
                self.x.hypot(self.y)
            }
            /// Direction of `other` seen from `self` [rad], in this frame.
            pub fn bearing_to(self, other: Self) -> f64 {
                (other.y - self.y).atan2(other.x - self.x)
            }
            pub fn lerp(self, other: Self, t: f64) -> Self {
                Self::new(self.x + (other.x - self.x) * t, self.y + (other.y - self.y) * t)
            }
            pub fn scaled(self, k: f64) -> Self {
                Self::new(self.x * k, self.y * k)
            }
        }

        impl Add for $name {
            type Output = $name;
            fn add(self, o: $name) -> $name {
                $name::new(self.x + o.x, self.y + o.y)
            }
        }

        impl Sub for $name {
            type Output = $name;
            fn sub(self, o: $name) -> $name {
                $name::new(self.x - o.x, self.y - o.y)
            }
        }
    };
}

planar_point!(
    /// A point (or offset) in the server's global field frame [m].
    Global
);
planar_point!(
    /// A point (or offset) in the team's own frame [m]: own goal at −x.
    Own
);
planar_point!(
    /// A point (or offset) in the robot frame [m]: x forwards, y left.
    Robot
);

/// Which way round the team plays: the one global ↔ own conversion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TeamSide {
    mirrored: bool,
}

impl TeamSide {
    /// The team's side as the server told it; unknown counts as left (global = own).
    pub fn of(side: Option<Side>) -> Self {
        Self {
            mirrored: side == Some(Side::Right),
        }
    }

    pub fn own(self, p: Global) -> Own {
        if self.mirrored {
            Own::new(-p.x, -p.y)
        } else {
            Own::new(p.x, p.y)
        }
    }

    pub fn global(self, p: Own) -> Global {
        if self.mirrored {
            Global::new(-p.x, -p.y)
        } else {
            Global::new(p.x, p.y)
        }
    }

    /// A global heading [deg] in the own frame (and back: the turn is its own inverse).
    pub fn own_heading_deg(self, yaw_deg: f64) -> f64 {
        if self.mirrored {
            crate::geometry::wrap_deg(yaw_deg + 180.0)
        } else {
            yaw_deg
        }
    }
}

/// The robot's place on the field: global position and heading [deg, + counter-clockwise].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Pose {
    pub position: Global,
    pub yaw_deg: f64,
}

impl Pose {
    pub fn new(position: Global, yaw_deg: f64) -> Self {
        Self { position, yaw_deg }
    }

    /// A global point as the robot sees it.
    pub fn robot(&self, p: Global) -> Robot {
        let (s, c) = self.yaw_deg.to_radians().sin_cos();
        let d = p - self.position;
        Robot::new(c * d.x + s * d.y, -s * d.x + c * d.y)
    }

    /// A robot-frame point on the field.
    pub fn global(&self, p: Robot) -> Global {
        let (s, c) = self.yaw_deg.to_radians().sin_cos();
        self.position + Global::new(c * p.x - s * p.y, s * p.x + c * p.y)
    }

    /// A global direction [rad] relative to the robot's heading, wrapped to (−π, π].
    pub fn relative_angle(&self, global_rad: f64) -> f64 {
        let a = global_rad - self.yaw_deg.to_radians();
        a.sin().atan2(a.cos())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn own_frame_mirrors_for_the_right_team_only() {
        let p = Global::new(3.0, -2.0);
        assert_eq!(TeamSide::of(Some(Side::Left)).own(p), Own::new(3.0, -2.0));
        let right = TeamSide::of(Some(Side::Right));
        assert_eq!(right.own(p), Own::new(-3.0, 2.0));
        assert_eq!(right.global(right.own(p)), p);
        assert!((right.own_heading_deg(10.0) - -170.0).abs() < 1e-9);
    }

    #[test]
    fn robot_frame_round_trips_and_faces_along_the_heading() {
        let pose = Pose::new(Global::new(1.0, 1.0), 90.0);
        // Facing +y: a point 2 m further along +y is straight ahead.
        let ahead = pose.robot(Global::new(1.0, 3.0));
        assert!(
            (ahead.x - 2.0).abs() < 1e-9 && ahead.y.abs() < 1e-9,
            "{ahead:?}"
        );
        // A point at −x globally is on the robot's left.
        let left = pose.robot(Global::new(0.0, 1.0));
        assert!(
            left.x.abs() < 1e-9 && (left.y - 1.0).abs() < 1e-9,
            "{left:?}"
        );
        let back = pose.global(Robot::new(0.3, -0.7));
        let again = pose.robot(back);
        assert!((again.x - 0.3).abs() < 1e-12 && (again.y + 0.7).abs() < 1e-12);
        assert!((pose.relative_angle(0.0) + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }
}
