//! The tree language: its syntax tree, reading it from RON and writing it back.

mod ast;
mod parse;
mod print;
mod utility;

pub use ast::*;
pub use parse::parse_behavior_file;
pub use print::print_behavior_file;

/// The built-in nodes of the language, for `libero nodes`.
pub const LANGUAGE: &[(&str, &str)] = &[
    ("Sequence([..])", "Ticks children in order; fails at the first failure, remembers the running child."),
    ("Fallback([..])", "Ticks children in order; succeeds at the first success, remembers the running child."),
    ("ReactiveSequence([..])", "Like Sequence but restarts from the first child every tick, halting later running children."),
    ("ReactiveFallback([..])", "Like Fallback but restarts from the first child every tick, halting later running children."),
    ("Parallel(success: k, failure: m, children: [..])", "Ticks all children; succeeds when k succeeded, fails when m failed."),
    ("Invert(child)", "Swaps Success and Failure."),
    ("ForceSuccess(child)", "Success once the child completes, whatever its result."),
    ("ForceFailure(child)", "Failure once the child completes, whatever its result."),
    ("Repeat(n: n, child: ..)", "Runs the child n times in a row, one run per tick; fails when it fails."),
    ("RetryUntilSuccess(n: n, child: ..)", "Runs the child up to n times until it succeeds, one attempt per tick."),
    ("Timeout(seconds: s, child: ..)", "Fails and halts the child when it has run longer than s seconds."),
    ("Cooldown(seconds: s, child: ..)", "After the child succeeds, fails without ticking it for s seconds."),
    ("Utility(hysteresis: h, choices: [Choice(weight, considerations, child)])", "Runs the best-scored choice; the running choice keeps a bonus h against switching."),
    ("Consider(input: expr, curve: Curve, weight: w)", "One scored input of a Choice: a numeric value through a response curve in [0, 1]."),
    ("Linear(from, to) | Power(from, to, exponent) | Logistic(mid, steepness) | Step(threshold, above) | Identity", "Response curves of a consideration."),
    ("Condition(name: \"N\", param: expr, ..)", "A native condition: Success when true."),
    ("Action(name: \"N\", param: expr, ..)", "A native action, ticked every cycle while Running and halted when abandoned."),
    ("SubTree(name: \"T\", param: expr, ..)", "Runs tree T with its declared parameters bound to the given values."),
    ("Compare(left: expr, op: \"<\", right: expr)", "Compares two values (<, <=, >, >=, ==, !=)."),
    ("Set(key: \"k\", value: expr)", "Writes a blackboard entry and succeeds."),
    ("Wait(seconds: s)", "Running for s seconds, then Success."),
    ("Succeed | Fail", "Constant Success or Failure."),
    ("expr: 1.5 | 3 | true | \"text\" | (x, y) | Bb(\"key\") | Param(\"name\") | Query(\"q\") | Query(name: \"q\", param: expr)", "Values: constants, blackboard entries, subtree parameters or named world queries."),
];

/// Reads one behavior file's text; the report holds every syntax and shape error.
pub fn read_behavior_file(path: &std::path::Path, text: &str) -> (BehaviorFile, crate::Report) {
    let source = std::sync::Arc::new(crate::diagnostics::SourceFile::new(
        path.to_path_buf(),
        text.to_string(),
    ));
    let mut report = crate::Report::default();
    let file = match crate::syntax::parse(text) {
        Ok(node) => {
            parse_behavior_file(&mut crate::decode::Decoder::new(source, &mut report), &node)
        }
        Err(error) => {
            report.push(
                crate::Diagnostic::error("syntax", error.message)
                    .at(&source, error.span)
                    .maybe_hint(error.hint),
            );
            BehaviorFile::default()
        }
    };
    (file, report)
}
