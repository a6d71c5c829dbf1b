//! Per-cycle wire cost on real samples: parse a T1 percept with vision, encode 23 motor
//! commands. Printed beside a baseline that does the same work the obvious way (build an owned
//! tree of `String`s, format floats with `format!`) so the figure is a ratio, not a wall time.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use libero_model::{RobotModel, ServerKind};
use libero_protocol::{parse_percept_str, ActionWriter, MotorCommand};

const T1_WITH_VISION: &str =
    include_str!("../../../../shared/samples/rcssservermj/T1_two_agents_B_with_MIC_012.txt");

fn ours(model: &RobotModel, writer: &mut ActionWriter, out: &mut Vec<u8>) -> usize {
    let p = parse_percept_str(T1_WITH_VISION, ServerKind::RcssMj).unwrap();
    writer.clear();
    out.clear();
    for (joint, reading) in model.joints.iter().zip(&p.joints) {
        let cmd = MotorCommand {
            q_deg: reading.angle_deg,
            dq_deg: 0.0,
            kp: joint.gains.kp,
            kd: joint.gains.kd,
            tau: 0.0,
        };
        writer.motor(joint, cmd);
    }
    writer.frame_into(out);
    out.len() + p.vision.map_or(0, |v| v.landmarks.len())
}

/// Owned S-expression tree: the usual first implementation.
enum Owned {
    Atom(String),
    List(Vec<Owned>),
}

fn parse_owned(text: &str) -> Vec<Owned> {
    let mut stack: Vec<Vec<Owned>> = vec![Vec::new()];
    let mut atom = String::new();
    for c in text.chars() {
        match c {
            '(' | ')' | ' ' => {
                if !atom.is_empty() {
                    stack
                        .last_mut()
                        .unwrap()
                        .push(Owned::Atom(std::mem::take(&mut atom)));
                }
                if c == '(' {
                    stack.push(Vec::new());
                } else if c == ')' {
                    let list = stack.pop().unwrap();
                    stack.last_mut().unwrap().push(Owned::List(list));
                }
            }
            _ => atom.push(c),
        }
    }
    stack.pop().unwrap()
}

fn count_numbers(items: &[Owned]) -> usize {
    items
        .iter()
        .map(|i| match i {
            Owned::Atom(a) => a.parse::<f64>().is_ok() as usize,
            Owned::List(l) => count_numbers(l),
        })
        .sum()
}

fn baseline(model: &RobotModel) -> usize {
    let tree = parse_owned(T1_WITH_VISION);
    let mut msg = String::new();
    for joint in &model.joints {
        msg += &format!(
            "({} {:.3} {:.3} {:.2} {:.3} {:.3})",
            joint.effector, 1.5, 0.0, joint.gains.kp, joint.gains.kd, 0.0
        );
    }
    count_numbers(&tree) + msg.len()
}

fn cycle(c: &mut Criterion) {
    let model = RobotModel::builtin("T1").unwrap();
    let mut writer = ActionWriter::new(ServerKind::RcssMj);
    let mut out = Vec::new();
    let mut group = c.benchmark_group("t1_cycle_parse_and_encode");
    group.bench_function("libero", |b| {
        b.iter(|| black_box(ours(&model, &mut writer, &mut out)))
    });
    group.bench_function("baseline_owned_tree_and_format", |b| {
        b.iter(|| black_box(baseline(&model)))
    });
    group.finish();
}

criterion_group!(benches, cycle);
criterion_main!(benches);
