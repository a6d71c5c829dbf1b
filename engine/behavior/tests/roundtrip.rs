//! Random valid trees survive printing to RON and reading back, and the printed text is RON
//! that the `ron` crate accepts.

use libero_behavior::syntax::Span;
use libero_behavior::tree::*;
use libero_behavior::{Value, ValueType, Vec2};
use proptest::prelude::*;

fn span() -> Span {
    Span::default()
}

fn name() -> impl Strategy<Value = String> {
    "[A-Za-z][A-Za-z0-9_]{0,8}"
}

/// Argument names: identifiers other than the reserved `name` and RON's keywords.
fn arg_name() -> impl Strategy<Value = String> {
    "[a-z][a-z_]{0,6}".prop_filter("reserved", |n| {
        !matches!(n.as_str(), "name" | "true" | "false" | "inf")
    })
}

fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![(-1e6f64..1e6), Just(0.0), Just(-0.5), Just(1e-7)]
}

fn constant() -> impl Strategy<Value = Value> {
    prop_oneof![
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(Value::Int),
        finite().prop_map(Value::Float),
        (finite(), finite()).prop_map(|(x, y)| Value::Vec2(Vec2::new(x, y))),
        "[ -~é\\n\\t\"\\\\]{0,12}".prop_map(|s| Value::String(s.into())),
    ]
}

fn expr() -> impl Strategy<Value = Expr> {
    let leaf = prop_oneof![
        constant().prop_map(ExprKind::Const),
        name().prop_map(ExprKind::Blackboard),
        name().prop_map(ExprKind::Param),
        name().prop_map(|n| ExprKind::Query(call(n, vec![]))),
    ];
    leaf.prop_map(|kind| Expr { kind, span: span() })
        .prop_recursive(2, 6, 2, |inner| {
            (name(), prop::collection::vec((arg_name(), inner), 0..3)).prop_map(|(n, args)| Expr {
                kind: ExprKind::Query(call(
                    n,
                    args.into_iter()
                        .map(|(a, value)| Arg {
                            name: a,
                            name_span: span(),
                            value,
                        })
                        .collect(),
                )),
                span: span(),
            })
        })
}

fn call(name: String, args: Vec<Arg>) -> Call {
    Call {
        name,
        name_span: span(),
        args,
        invalid_args: vec![],
    }
}

fn leaf_call() -> impl Strategy<Value = Call> {
    (name(), prop::collection::vec((arg_name(), expr()), 0..3)).prop_map(|(n, args)| {
        let args = args
            .into_iter()
            .map(|(a, value)| Arg {
                name: a,
                name_span: span(),
                value,
            })
            .collect();
        call(n, args)
    })
}

fn curve() -> impl Strategy<Value = Curve> {
    prop_oneof![
        Just(Curve::Identity),
        (finite(), finite()).prop_map(|(from, to)| Curve::Linear { from, to }),
        (finite(), finite(), finite()).prop_map(|(from, to, exponent)| Curve::Power {
            from,
            to,
            exponent
        }),
        (finite(), finite()).prop_map(|(mid, steepness)| Curve::Logistic { mid, steepness }),
        (finite(), any::<bool>()).prop_map(|(threshold, above)| Curve::Step { threshold, above }),
    ]
}

fn node() -> impl Strategy<Value = NodeDef> {
    let leaf = prop_oneof![
        leaf_call().prop_map(NodeDefKind::Condition),
        leaf_call().prop_map(NodeDefKind::Action),
        leaf_call().prop_map(NodeDefKind::SubTree),
        (expr(), 0usize..6, expr()).prop_map(|(left, op, right)| NodeDefKind::Compare {
            left,
            op: CompareOp::ALL[op],
            right
        }),
        (name(), expr()).prop_map(|(key, value)| NodeDefKind::Set {
            key,
            key_span: span(),
            value
        }),
        (0.0f64..3600.0).prop_map(NodeDefKind::Wait),
        Just(NodeDefKind::Succeed),
        Just(NodeDefKind::Fail),
    ];
    let leaf = leaf.prop_map(|kind| NodeDef {
        kind,
        span: span(),
        head_span: span(),
    });
    leaf.prop_recursive(4, 32, 4, |inner| {
        let boxed = inner.clone().prop_map(Box::new);
        prop_oneof![
            (0usize..4, prop::collection::vec(inner.clone(), 1..4))
                .prop_map(|(k, c)| NodeDefKind::Composite(CompositeKind::ALL[k], c)),
            (1u32..5, 1u32..5, prop::collection::vec(inner.clone(), 1..4)).prop_map(
                |(success, failure, children)| NodeDefKind::Parallel {
                    success,
                    failure,
                    threshold_span: span(),
                    children
                }
            ),
            (0usize..3, boxed.clone())
                .prop_map(|(k, c)| NodeDefKind::Decorator(DecoratorKind::ALL[k], c)),
            (any::<bool>(), 1u32..10_000, boxed.clone()).prop_map(|(r, n, c)| {
                NodeDefKind::Counted(
                    if r {
                        CountKind::Repeat
                    } else {
                        CountKind::RetryUntilSuccess
                    },
                    n,
                    c,
                )
            }),
            (any::<bool>(), 0.0f64..3600.0, boxed).prop_map(|(t, s, c)| {
                NodeDefKind::Timed(
                    if t {
                        TimedKind::Timeout
                    } else {
                        TimedKind::Cooldown
                    },
                    s,
                    c,
                )
            }),
            (
                0.0f64..1.0,
                prop::collection::vec(
                    (
                        0.0f64..100.0,
                        prop::collection::vec((expr(), curve(), 0.0f64..100.0), 0..3),
                        inner
                    ),
                    1..3
                )
            )
                .prop_map(|(hysteresis, choices)| NodeDefKind::Utility {
                    hysteresis,
                    choices: choices
                        .into_iter()
                        .map(|(weight, considerations, child)| Choice {
                            weight,
                            considerations: considerations
                                .into_iter()
                                .map(|(input, curve, weight)| Consideration {
                                    input,
                                    curve,
                                    weight
                                })
                                .collect(),
                            child,
                            span: span(),
                        })
                        .collect(),
                }),
        ]
        .prop_map(|kind| NodeDef {
            kind,
            span: span(),
            head_span: span(),
        })
    })
}

fn behavior_file() -> impl Strategy<Value = BehaviorFile> {
    let decl = (name(), constant()).prop_map(|(key, initial)| BlackboardDecl {
        key,
        key_span: span(),
        ty: initial.value_type(),
        initial,
    });
    let param =
        (name(), 0usize..5, prop::option::of(constant())).prop_map(|(name, ty, default)| {
            match default {
                Some(value) => TreeParam {
                    name,
                    span: span(),
                    ty: value.value_type(),
                    default: Some(value),
                },
                None => TreeParam {
                    name,
                    span: span(),
                    ty: ValueType::ALL[ty],
                    default: None,
                },
            }
        });
    let tree =
        (name(), prop::collection::vec(param, 0..3), node()).prop_map(|(name, params, root)| {
            TreeDef {
                name,
                name_span: span(),
                params,
                root,
            }
        });
    (
        prop::collection::vec(decl, 0..3),
        prop::collection::vec(tree, 1..4),
    )
        .prop_map(|(blackboard, trees)| BehaviorFile { blackboard, trees })
}

fn parse(text: &str) -> (BehaviorFile, libero_behavior::Report) {
    read_behavior_file(std::path::Path::new("p.ron"), text)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_trees_round_trip_through_ron(file in behavior_file()) {
        let printed = print_behavior_file(&file);
        let (read_back, report) = parse(&printed);
        prop_assert!(report.diagnostics.is_empty(), "{}\n{printed}", report.render_text());
        prop_assert_eq!(print_behavior_file(&read_back), printed.clone());
        prop_assert_eq!(read_back.trees.len(), file.trees.len());
        prop_assert!(ron::from_str::<ron::Value>(&printed).is_ok(), "not valid RON:\n{}", printed);
    }
}
