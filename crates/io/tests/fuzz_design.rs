//! Fuzzing the design file reader (`*.oficina.json`) with proptest: a valid design with
//! every kind of entity, mutated (bytes overwritten, JSON tokens and absurd numbers spliced
//! in, cut short). Asserted for every input: no panic; a result is either an error naming
//! the file, or a drawing whose every point is finite (the reader refuses numbers beyond
//! ±10⁶ mm and non-positive radii before anything is built from them).
//!
//! Cases: `PROPTEST_CASES` (default 256).

use oficina_io::design_from_bytes;
use proptest::prelude::*;

const DESIGN: &str = include_str!("data/design/every_entity.oficina.json");

/// What gets spliced in: JSON structure, absurd numbers, wrong types.
const TOKENS: &[&str] = &[
    "1e308",
    "-1e308",
    "1e-320",
    "NaN",
    "Infinity",
    "-0",
    "1e6",
    "1000001",
    "0",
    "-4",
    "18446744073709551616",
    "[",
    "]",
    "{",
    "}",
    ",",
    ":",
    "\"",
    "null",
    "true",
    "\"arc\"",
    "\"polyline\"",
    "\"text\"",
    "[[0,0]]",
    "[]",
    "{}",
    "\"\\u0000\"",
];

#[derive(Clone, Debug)]
enum Mutation {
    Overwrite(usize, u8),
    Splice(usize, usize, usize),
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Overwrite(i, b)),
        (any::<usize>(), 0..12usize, 0..TOKENS.len())
            .prop_map(|(i, n, t)| Mutation::Splice(i, n, t)),
        any::<usize>().prop_map(Mutation::Truncate),
    ]
}

fn mutate(mut bytes: Vec<u8>, mutations: &[Mutation]) -> Vec<u8> {
    for m in mutations {
        let len = bytes.len().max(1);
        match *m {
            Mutation::Overwrite(i, b) => {
                if !bytes.is_empty() {
                    bytes[i % len] = b;
                }
            }
            Mutation::Splice(i, n, t) => {
                let at = (i % len).min(bytes.len());
                let end = (at + n).min(bytes.len());
                bytes.splice(at..end, TOKENS[t].bytes());
            }
            Mutation::Truncate(i) => bytes.truncate(i % len),
        }
    }
    bytes
}

proptest! {
    #[test]
    fn a_mutated_design_is_read_or_refused_by_name(mutations in prop::collection::vec(mutation(), 1..6)) {
        let bytes = mutate(DESIGN.as_bytes().to_vec(), &mutations);
        match design_from_bytes(&bytes, "fuzz.oficina.json") {
            Err(e) => prop_assert!(e.to_string().contains("fuzz.oficina.json"), "{e}"),
            Ok(imported) => {
                for layer in &imported.drawing.layers {
                    for path in &layer.paths {
                        for s in &path.segments {
                            for k in 0..=4 {
                                let p = s.eval(k as f64 / 4.0);
                                prop_assert!(p.x.is_finite() && p.y.is_finite(), "{p:?} in {:?}", path.source);
                            }
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn the_unmutated_design_reads() {
    let imported = design_from_bytes(DESIGN.as_bytes(), "fuzz.oficina.json").unwrap();
    assert_eq!(imported.drawing.layers.len(), 2);
}
