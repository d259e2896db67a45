//! Fuzzing the design file reader (`*.oficina.json`) with proptest: a valid design with
//! every kind of entity, mutated (bytes overwritten, JSON tokens and absurd numbers spliced
//! in, cut short). Asserted for every input: no panic; a result is either an error naming
//! the file, or a drawing whose every point is finite (the reader refuses numbers beyond
//! ±10⁶ mm and non-positive radii before anything is built from them).
//!
//! Cases: `PROPTEST_CASES` (default 256).

use oficina_io::design_from_bytes;
use proptest::prelude::*;

const DESIGN: &str = r##"{
  "format": "oficina-design", "version": 1,
  "layers": [{"name": "OUTLINE", "color": "#ff0000"}, {"name": "holes", "color": "#0000ff"}],
  "entities": [
    {"id": 1, "layer": "OUTLINE", "type": "polyline", "closed": true,
     "vertices": [[0, 0], [60, 0], [60, 35, 0.41421356237309503], [55, 40], [0, 40]]},
    {"id": 2, "layer": "OUTLINE", "type": "line", "a": [5, 5], "b": [25.5, 12.25]},
    {"id": 3, "layer": "OUTLINE", "type": "arc", "center": [30, 20], "radius": 7.5, "start": 10, "sweep": 200},
    {"id": 4, "layer": "OUTLINE", "type": "arc", "center": [45, 20], "radius": 3, "start": 90, "sweep": -135},
    {"id": 5, "layer": "holes", "type": "circle", "center": [12, 30], "radius": 4},
    {"id": 6, "layer": "holes", "type": "spline", "points": [[5, 15], [15, 22], [25, 18], [33, 27]]},
    {"id": 7, "layer": "holes", "type": "text", "at": [35, 5], "height": 5, "text": "Oz"}
  ],
  "process": {"tool": "flat:3", "depth": 4.2}
}"##;

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
