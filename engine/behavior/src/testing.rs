//! A fixture vocabulary (native nodes shaped like a soccer agent's, with no behaviour behind
//! them) and a scripted host, for the tree engine's own tests and benchmarks. Real domains
//! declare their nodes themselves (the strategy crate).

use crate::runtime::{Args, Host};
use crate::value::{Status, Value, ValueType, Vec2};
use crate::vocabulary::{NativeId, NodeSpec, ParamSpec, Vocabulary};
use std::collections::HashMap;

/// Play modes as seen from the team (own/theirs rather than left/right).
pub const PLAY_MODES: &[&str] = &[
    "BeforeKickOff",
    "KickOffOwn",
    "KickOffTheirs",
    "PlayOn",
    "ThrowInOwn",
    "ThrowInTheirs",
    "CornerKickOwn",
    "CornerKickTheirs",
    "GoalKickOwn",
    "GoalKickTheirs",
    "FreeKickOwn",
    "FreeKickTheirs",
    "GoalOwn",
    "GoalTheirs",
    "GameOver",
];

/// Example native nodes for tests of the engine.
pub fn example_vocabulary() -> Vocabulary {
    {
        use ValueType::*;
        Vocabulary::new()
            .with(
                NodeSpec::condition("PlayModeIs", "True when the current play mode is `mode`.")
                    .param(
                        ParamSpec::new("mode", String)
                            .choices(PLAY_MODES)
                            .doc("team-relative play mode"),
                    ),
            )
            .with(NodeSpec::condition(
                "CanBeam",
                "True when the server accepts a beam (before kick-off, after a goal).",
            ))
            .with(NodeSpec::condition(
                "IsFallen",
                "True when the robot is lying on the ground.",
            ))
            .with(NodeSpec::action(
                "BeamToFormation",
                "Beams to this player's kick-off formation position; succeeds when placed.",
            ))
            .with(NodeSpec::action(
                "Stand",
                "Holds the standing pose (getting up first if fallen); succeeds when stable.",
            ))
            .with(
                NodeSpec::action(
                    "LookAround",
                    "Pans the head to scan the field; runs until halted.",
                )
                .param(
                    ParamSpec::new("amplitude", Float)
                        .unit("rad")
                        .range(0.0, 2.0)
                        .default(Value::Float(1.2))
                        .doc("pan half-range"),
                )
                .param(
                    ParamSpec::new("period", Float)
                        .unit("s")
                        .range(0.2, 20.0)
                        .default(Value::Float(4.0))
                        .doc("time for a full sweep"),
                ),
            )
            .with(
                NodeSpec::action(
                    "WalkTo",
                    "Walks to a field point; succeeds within `tolerance`.",
                )
                .param(
                    ParamSpec::new("target", Vec2)
                        .unit("m")
                        .doc("destination, own frame"),
                )
                .param(
                    ParamSpec::new("speed", Float)
                        .unit("m/s")
                        .range(0.0, 2.0)
                        .default(Value::Float(0.6))
                        .doc("walking speed"),
                )
                .param(
                    ParamSpec::new("tolerance", Float)
                        .unit("m")
                        .range(0.05, 5.0)
                        .default(Value::Float(0.3))
                        .doc("arrival radius"),
                ),
            )
            .with(
                NodeSpec::action(
                    "KickTo",
                    "Kicks the ball towards a field point: the kick skill walks to its kicking place behind the ball from any side, then kicks (short or long by distance). Succeeds once the kick skill reports the kick done; fails when the ball has not been seen for `lost_after` seconds.",
                )
                .param(
                    ParamSpec::new("target", Vec2)
                        .unit("m")
                        .doc("where the ball should go, own frame"),
                )
                .param(
                    ParamSpec::new("distance", Float)
                        .unit("m")
                        .range(0.0, 40.0)
                        .default(Value::Float(0.0))
                        .doc("how far to kick; 0 = as far as the target"),
                )
                .param(
                    ParamSpec::new("lost_after", Float)
                        .unit("s")
                        .range(0.5, 30.0)
                        .default(Value::Float(4.0))
                        .doc("give up when the ball is unseen this long"),
                ),
            )
            .with(NodeSpec::query(
                "opponent_goal",
                Vec2,
                "Centre of the opponent's goal line (m, own frame).",
            ))
            .with(NodeSpec::query(
                "ball_position",
                Vec2,
                "Estimated ball position (m, own frame).",
            ))
            .with(NodeSpec::query(
                "ball_distance",
                Float,
                "Distance from the robot to the ball (m).",
            ))
            .with(NodeSpec::query(
                "my_position",
                Vec2,
                "Estimated robot position (m, own frame).",
            ))
            .with(NodeSpec::query(
                "formation_position",
                Vec2,
                "This player's formation position for the situation and ball (m).",
            ))
            .with(NodeSpec::query(
                "play_time",
                Float,
                "Seconds since kick-off of the half.",
            ))
            .with(NodeSpec::query(
                "am_closest_to_ball",
                Bool,
                "True when no teammate is closer to the ball.",
            ))
    }
}

/// A host whose world is a table of values and whose actions return scripted statuses; it
/// records every call so tests can assert what ran.
#[derive(Debug, Default)]
pub struct ScriptedHost {
    pub time: f64,
    pub queries: HashMap<String, Value>,
    pub conditions: HashMap<String, bool>,
    /// Status per action name; actions not listed return Running.
    pub actions: HashMap<String, Status>,
    /// Every action call as (name, args).
    pub calls: Vec<(String, Vec<Value>)>,
    /// Every halt as action name.
    pub halts: Vec<String>,
    names: Vec<String>,
}

impl ScriptedHost {
    pub fn new(vocabulary: &Vocabulary) -> Self {
        let names = vocabulary.nodes().iter().map(|n| n.name.clone()).collect();
        let mut host = Self {
            names,
            ..Self::default()
        };
        host.queries
            .insert("ball_position".into(), Value::Vec2(Vec2::new(0.0, 0.0)));
        host.queries
            .insert("ball_distance".into(), Value::Float(5.0));
        host.queries
            .insert("my_position".into(), Value::Vec2(Vec2::new(-10.0, 0.0)));
        host.queries.insert(
            "formation_position".into(),
            Value::Vec2(Vec2::new(-8.0, 2.0)),
        );
        host.queries.insert("play_time".into(), Value::Float(0.0));
        host.queries
            .insert("opponent_goal".into(), Value::Vec2(Vec2::new(14.0, 0.0)));
        host.queries
            .insert("am_closest_to_ball".into(), Value::Bool(false));
        host
    }

    pub fn name(&self, id: NativeId) -> &str {
        &self.names[id.0 as usize]
    }

    /// Names of the actions called, in order.
    pub fn action_names(&self) -> Vec<&str> {
        self.calls.iter().map(|(n, _)| n.as_str()).collect()
    }
}

impl Host for ScriptedHost {
    fn now(&self) -> f64 {
        self.time
    }

    fn query(&self, id: NativeId, _args: Args) -> Value {
        self.queries
            .get(self.name(id))
            .cloned()
            .unwrap_or(Value::Bool(false))
    }

    fn condition(&self, id: NativeId, args: Args) -> bool {
        let name = self.name(id);
        if name == "PlayModeIs" {
            let mode = self
                .queries
                .get("play_mode")
                .map(|v| v.as_str().to_string())
                .unwrap_or_default();
            return mode == args.str(0);
        }
        self.conditions.get(name).copied().unwrap_or(false)
    }

    fn action(&mut self, id: NativeId, args: Args) -> Status {
        let name = self.name(id).to_string();
        let status = self.actions.get(&name).copied().unwrap_or(Status::Running);
        self.calls.push((name, args.0.to_vec()));
        status
    }

    fn halt(&mut self, id: NativeId, _args: Args) {
        let name = self.name(id).to_string();
        self.halts.push(name);
    }
}
