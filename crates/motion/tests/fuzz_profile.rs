//! Fuzzing machine profile loading with proptest: random text, and the bundled profiles with
//! values replaced by absurd ones, lines dropped, repeated or garbled.
//!
//! Asserted for every input: no panic; a profile that loads can plan a short program (a
//! straight move, an arc, a return) to its end within a bounded number of segments, and its
//! kinematics answer for the start position.
//!
//! Cases per property: proptest's `PROPTEST_CASES` (default 256); a long run:
//! `PROPTEST_CASES=100000 cargo test --release -p oficina-motion --test fuzz_profile`.

mod common;

use oficina_canon::{Canon, CanonOp, Plane, Pos};
use oficina_motion::{for_profile, Kinematics};
use oficina_motion::{plan, PlanOptions, Profile};
use proptest::prelude::*;

const BUNDLED: [&str; 5] = [
    include_str!("../../../profiles/grbl-router.toml"),
    include_str!("../../../profiles/hotwire-xy.toml"),
    include_str!("../../../profiles/polar-plotter.toml"),
    include_str!("../../../profiles/polargraph-wall.toml"),
    include_str!("../../../profiles/embroidery-xy.toml"),
];

/// Values a user (or a broken editor) may put where a number, string or table belongs.
const ABSURD: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "nan",
    "inf",
    "-inf",
    "1e30",
    "1e-30",
    "9223372036854775807",
    "-9223372036854775808",
    "\"\"",
    "\"polar\"",
    "\"scurve\"",
    "\"corexy\"",
    "\"polargraph\"",
    "[]",
    "[1e308, -1e308]",
    "[nan, 1]",
    "[0, 0]",
    "[1, 2, 3]",
    "true",
    "{}",
    "{ direction = \"positive\", seek_rate = 1e-300, feed_rate = 1e300 }",
];

#[derive(Debug, Clone)]
enum Edit {
    Value(usize, usize),
    Drop(usize),
    Repeat(usize),
    Insert(usize, String),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        4 => (any::<usize>(), 0..ABSURD.len()).prop_map(|(l, v)| Edit::Value(l, v)),
        1 => any::<usize>().prop_map(Edit::Drop),
        1 => any::<usize>().prop_map(Edit::Repeat),
        1 => (any::<usize>(), "[ -~]{0,40}").prop_map(|(l, s)| Edit::Insert(l, s)),
    ]
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for e in edits {
        if lines.is_empty() {
            break;
        }
        let n = lines.len();
        match e {
            Edit::Value(l, v) => {
                let line = &mut lines[l % n];
                if let Some(eq) = line.find('=') {
                    *line = format!("{}= {}", &line[..eq], ABSURD[*v]);
                }
            }
            Edit::Drop(l) => {
                lines.remove(l % n);
            }
            Edit::Repeat(l) => {
                let copy = lines[l % n].clone();
                lines.insert(l % n, copy);
            }
            Edit::Insert(l, s) => lines.insert(l % (n + 1), s.clone()),
        }
    }
    lines.join("\n")
}

/// A short program a quarter of the way from the middle of the travel to its corner (the
/// middle of a polar machine is its pivot): out, round an arc, back.
fn program(p: &Profile) -> Vec<Canon> {
    let mid = |i: usize| (p.travel[i][0] * 3.0 + p.travel[i][1] * 5.0) / 8.0;
    let (x, y, z) = (mid(0), mid(1), p.start[2]);
    let r = ((p.travel[0][1] - p.travel[0][0]) / 8.0).min(50.0);
    let ops = [
        CanonOp::SetFeedRate(600.0),
        CanonOp::StraightTraverse {
            to: Pos::xyz(x, y, z),
        },
        CanonOp::StraightFeed {
            to: Pos::xyz(x + r, y, z),
        },
        CanonOp::ArcFeed {
            plane: Plane::XY,
            end: Pos::xyz(x - r, y, z),
            center: [x, y],
            turns: 1,
            rotation: 0.0,
        },
        CanonOp::StraightTraverse {
            to: Pos::xyz(p.start[0], p.start[1], p.start[2]),
        },
        CanonOp::ProgramEnd,
    ];
    common::numbered(ops)
}

/// Segments a sane profile needs for the program, many times over: more means a runaway.
const SEGMENT_BOUND: usize = 2_000_000;

fn exercise(text: &str) {
    let Ok(p) = Profile::parse(text, "fuzz.toml") else {
        return;
    };
    let _ = for_profile(&p).joints(p.start);
    let Ok(planner) = plan(program(&p).into_iter(), &p, PlanOptions::default()) else {
        return;
    };
    let mut n = 0;
    for seg in planner {
        let Ok(seg) = seg else { break };
        assert!(
            seg.duration().is_finite() && seg.duration() >= 0.0,
            "{seg:?}"
        );
        n += 1;
        assert!(
            n < SEGMENT_BOUND,
            "no end in sight after {n} segments:\n{text}"
        );
    }
}

proptest! {
    #[test]
    fn random_text_never_panics(text in "\\PC{0,400}") {
        let _ = Profile::parse(&text, "fuzz.toml");
    }

    #[test]
    fn mutated_bundled_profiles_load_or_are_refused_and_plan(
        which in 0..BUNDLED.len(),
        edits in proptest::collection::vec(edit(), 1..6),
    ) {
        let t = apply(BUNDLED[which], &edits);
        exercise(&t);
    }
}

#[test]
fn the_bundled_profiles_themselves_plan() {
    for text in BUNDLED {
        let p = Profile::parse(text, "bundled").unwrap();
        let segs = plan(program(&p).into_iter(), &p, PlanOptions::default())
            .unwrap()
            .collect::<Result<Vec<_>, _>>();
        // Every bundled machine reaches the middle of its travel.
        assert!(segs.is_ok(), "{}: {:?}", p.name, segs.err());
    }
}

/// What the fuzzer found: a tolerance that cut a move into pieces without end, and a rate so
/// small that a move lasted forever. Both are refused, naming the key.
#[test]
fn profiles_the_fuzzer_found_are_refused_by_name() {
    let polar = BUNDLED[2].replace("path_tolerance = 0.05", "path_tolerance = 5e-324");
    let e = Profile::parse(&polar, "p.toml").unwrap_err().to_string();
    assert!(e.contains("planner.path_tolerance"), "{e}");
    let hotwire = BUNDLED[1].replacen("max_rate = 600.0", "max_rate = 1e-308", 1);
    assert_ne!(hotwire, BUNDLED[1]);
    let e = Profile::parse(&hotwire, "h.toml").unwrap_err().to_string();
    assert!(e.contains("max_rate"), "{e}");
}
