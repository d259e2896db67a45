//! Triangle meshes from STL (binary and ASCII) and OBJ files, in the file's own units (mm).
//!
//! Degenerate (zero-area) and repeated triangles are kept: drop-cutter tolerates both. What
//! is refused, with the file's name and the reason: empty files, a binary STL whose triangle
//! count does not match its length, non-finite coordinates, faces naming missing vertices,
//! and meshes that would need more memory than the budget (refused before allocating).

use std::path::Path;

/// A triangle soup, mm.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Triangles as three corners (x, y, z), mm.
    pub triangles: Vec<[[f64; 3]; 3]>,
}

/// Bytes one triangle costs in memory ([`Mesh`] plus the bucket grid's index).
pub const BYTES_PER_TRIANGLE: u64 = 72 + 16;

/// Why a mesh file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read.
    #[error("{path}: cannot read the mesh: {source}")]
    Read {
        /// The file.
        path: String,
        /// The system's reason.
        source: std::io::Error,
    },
    /// The content is not a mesh this reader accepts.
    #[error("{path}: {problem}")]
    Format {
        /// The file.
        path: String,
        /// What is wrong, with the line or triangle where it helps.
        problem: String,
    },
    /// The mesh would need more memory than allowed.
    #[error("{path}: {triangles} triangles need about {need_mb} MB, more than the {budget_mb} MB budget")]
    TooLarge {
        /// The file.
        path: String,
        /// Triangles the file declares (or could hold).
        triangles: u64,
        /// Estimated memory, MB.
        need_mb: u64,
        /// The budget, MB.
        budget_mb: u64,
    },
}

impl Mesh {
    /// Lowest and highest corner: `[min, max]`, mm (zeros for an empty mesh).
    pub fn bounds(&self) -> [[f64; 3]; 2] {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in self.triangles.iter().flatten() {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if self.triangles.is_empty() {
            return [[0.0; 3]; 2];
        }
        [lo, hi]
    }

    /// The mesh as ASCII STL text (normals left at 0: readers recompute them).
    pub fn to_ascii_stl(&self, name: &str) -> String {
        use std::fmt::Write;
        let mut s = format!("solid {name}\n");
        for t in &self.triangles {
            s.push_str(" facet normal 0 0 0\n  outer loop\n");
            for p in t {
                let _ = writeln!(s, "   vertex {:?} {:?} {:?}", p[0], p[1], p[2]);
            }
            s.push_str("  endloop\n endfacet\n");
        }
        let _ = writeln!(s, "endsolid {name}");
        s
    }

    /// Applies `f` to every corner.
    pub fn map(&mut self, f: impl Fn([f64; 3]) -> [f64; 3]) {
        for t in &mut self.triangles {
            for p in t.iter_mut() {
                *p = f(*p);
            }
        }
    }
}

/// Reads an STL (binary or ASCII) or OBJ file within `budget` bytes.
pub fn load_mesh(path: &Path, budget: u64) -> Result<Mesh, MeshError> {
    let name = path.display().to_string();
    let len = std::fs::metadata(path)
        .map_err(|source| MeshError::Read {
            path: name.clone(),
            source,
        })?
        .len();
    // The smallest text triangle ("f 1 2 3\n") is 8 bytes, a binary one 50: at most len/8
    // triangles, and the file itself is held while parsing.
    check_budget(&name, len / 8, len, budget)?;
    let bytes = std::fs::read(path).map_err(|source| MeshError::Read {
        path: name.clone(),
        source,
    })?;
    let is_obj = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    mesh_from_bytes(&name, &bytes, is_obj, budget)
}

fn check_budget(name: &str, triangles: u64, held: u64, budget: u64) -> Result<(), MeshError> {
    let need = triangles
        .saturating_mul(BYTES_PER_TRIANGLE)
        .saturating_add(held);
    if need > budget {
        return Err(MeshError::TooLarge {
            path: name.to_string(),
            triangles,
            need_mb: need.div_ceil(1 << 20),
            budget_mb: budget >> 20,
        });
    }
    Ok(())
}

/// Parses mesh bytes named `name`: OBJ when `is_obj`, else STL (binary or ASCII, told
/// apart by the binary length rule, not by the often misleading `solid` header).
pub fn mesh_from_bytes(
    name: &str,
    bytes: &[u8],
    is_obj: bool,
    budget: u64,
) -> Result<Mesh, MeshError> {
    let bad = |problem: String| MeshError::Format {
        path: name.to_string(),
        problem,
    };
    if bytes.is_empty() {
        return Err(bad("the file is empty (0 bytes)".into()));
    }
    let mesh = if is_obj {
        parse_obj(bytes, name, budget)?
    } else if is_binary_stl(bytes) {
        parse_binary(bytes, name, budget)?
    } else if bytes.trim_ascii_start().starts_with(b"solid") {
        parse_ascii(bytes, name, budget)?
    } else if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
        return Err(bad(format!(
            "binary STL declares {count} triangles ({} bytes) but the file has {} bytes: truncated or not an STL",
            84 + 50 * count,
            bytes.len()
        )));
    } else {
        return Err(bad(format!(
            "{} bytes: too short for a binary STL (84-byte header) and not an ASCII one",
            bytes.len()
        )));
    };
    if mesh.triangles.is_empty() {
        return Err(bad("no triangles".into()));
    }
    for (i, t) in mesh.triangles.iter().enumerate() {
        if t.iter().flatten().any(|v| !v.is_finite()) {
            return Err(bad(format!(
                "triangle {} has a non-finite coordinate (NaN or infinity): {t:?}",
                i + 1
            )));
        }
        if t.iter().flatten().any(|v| v.abs() > 1e6) {
            return Err(bad(format!(
                "triangle {} has a coordinate beyond 1 km: {t:?}",
                i + 1
            )));
        }
    }
    Ok(mesh)
}

fn is_binary_stl(bytes: &[u8]) -> bool {
    if bytes.len() < 84 {
        return false;
    }
    let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as u64;
    84 + 50 * count == bytes.len() as u64
}

fn parse_binary(bytes: &[u8], name: &str, budget: u64) -> Result<Mesh, MeshError> {
    let count = (bytes.len() - 84) / 50;
    check_budget(name, count as u64, bytes.len() as u64, budget)?;
    let f = |b: &[u8], i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]) as f64;
    let triangles = bytes[84..]
        .chunks_exact(50)
        .map(|r| {
            // 12 bytes of normal (ignored: recomputed from the corners), 3 corners, 2 spare.
            let p = |k: usize| [f(r, 12 + 12 * k), f(r, 16 + 12 * k), f(r, 20 + 12 * k)];
            [p(0), p(1), p(2)]
        })
        .collect();
    Ok(Mesh { triangles })
}

fn number(word: Option<&str>, name: &str, line: usize) -> Result<f64, MeshError> {
    let w = word.ok_or_else(|| MeshError::Format {
        path: name.into(),
        problem: format!("line {line}: a coordinate is missing"),
    })?;
    w.parse::<f64>().map_err(|_| MeshError::Format {
        path: name.into(),
        problem: format!("line {line}: '{w}' is not a number"),
    })
}

fn parse_ascii(bytes: &[u8], name: &str, budget: u64) -> Result<Mesh, MeshError> {
    let text = std::str::from_utf8(bytes).map_err(|e| MeshError::Format {
        path: name.into(),
        problem: format!("ASCII STL with invalid UTF-8 at byte {}", e.valid_up_to()),
    })?;
    // Every facet needs at least 3 "vertex" lines of ~20 bytes: budget checked in load_mesh;
    // here by the count of vertices met so far.
    let mut corners: Vec<[f64; 3]> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() == Some("vertex") {
            let p = [
                number(words.next(), name, i + 1)?,
                number(words.next(), name, i + 1)?,
                number(words.next(), name, i + 1)?,
            ];
            corners.push(p);
            if corners.len().is_multiple_of(3_000_000) {
                check_budget(name, corners.len() as u64 / 3, bytes.len() as u64, budget)?;
            }
        }
    }
    if !corners.len().is_multiple_of(3) {
        return Err(MeshError::Format {
            path: name.into(),
            problem: format!(
                "{} vertices is not a whole number of triangles: truncated?",
                corners.len()
            ),
        });
    }
    let triangles = corners
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Ok(Mesh { triangles })
}

fn parse_obj(bytes: &[u8], name: &str, budget: u64) -> Result<Mesh, MeshError> {
    let text = String::from_utf8_lossy(bytes);
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut triangles = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => vertices.push([
                number(words.next(), name, i + 1)?,
                number(words.next(), name, i + 1)?,
                number(words.next(), name, i + 1)?,
            ]),
            Some("f") => {
                let mut idx = Vec::new();
                for w in words {
                    // "7", "7/1", "7//3", "-1": the vertex index is the first field.
                    let first = w.split('/').next().unwrap_or("");
                    let k: i64 = first.parse().map_err(|_| MeshError::Format {
                        path: name.into(),
                        problem: format!("line {}: bad face index '{w}'", i + 1),
                    })?;
                    let n = vertices.len() as i64;
                    let at = if k < 0 { n + k } else { k - 1 };
                    if at < 0 || at >= n {
                        return Err(MeshError::Format {
                            path: name.into(),
                            problem: format!(
                                "line {}: face index {k} but {n} vertices so far",
                                i + 1
                            ),
                        });
                    }
                    idx.push(at as usize);
                }
                // A polygon becomes a fan of triangles.
                for j in 1..idx.len().saturating_sub(1) {
                    triangles.push([vertices[idx[0]], vertices[idx[j]], vertices[idx[j + 1]]]);
                }
                if triangles.len().is_multiple_of(1_000_000) {
                    check_budget(name, triangles.len() as u64, bytes.len() as u64, budget)?;
                }
            }
            _ => {}
        }
    }
    Ok(Mesh { triangles })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary(tris: &[[[f32; 3]; 3]], count: u32) -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b.extend(count.to_le_bytes());
        for t in tris {
            b.extend([0u8; 12]);
            for p in t {
                for v in p {
                    b.extend(v.to_le_bytes());
                }
            }
            b.extend([0u8; 2]);
        }
        b
    }

    const T: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]];

    #[test]
    fn binary_ascii_and_obj_agree() {
        let b = mesh_from_bytes("b.stl", &binary(&[T, T], 2), false, 1 << 30).unwrap();
        let a = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0.5\nendloop\nendfacet\nendsolid\n";
        let a = mesh_from_bytes("a.stl", a.as_bytes(), false, 1 << 30).unwrap();
        let o = "v 0 0 0\nv 1 0 0\nv 0 1 0.5\nf 1 2 3\n";
        let o = mesh_from_bytes("o.obj", o.as_bytes(), true, 1 << 30).unwrap();
        assert_eq!(b.triangles.len(), 2);
        assert_eq!(a.triangles[0], b.triangles[0]);
        assert_eq!(o.triangles[0], b.triangles[0]);
    }

    #[test]
    fn bad_files_are_named_and_explained() {
        let e = mesh_from_bytes("e.stl", b"", false, 1 << 30).unwrap_err();
        assert!(e.to_string().contains("e.stl") && e.to_string().contains("empty"));
        let mut b = binary(&[T], 1_000_000);
        b.truncate(134);
        let e = mesh_from_bytes("t.stl", &b, false, 1 << 30).unwrap_err();
        assert!(e.to_string().contains("declares 1000000"), "{e}");
        let nan = binary(&[[[f32::NAN, 0.0, 0.0], T[1], T[2]]], 1);
        let e = mesh_from_bytes("n.stl", &nan, false, 1 << 30).unwrap_err();
        assert!(e.to_string().contains("non-finite"), "{e}");
        let big = binary(&[[[1e9, 0.0, 0.0], T[1], T[2]]], 1);
        assert!(mesh_from_bytes("h.stl", &big, false, 1 << 30).is_err());
        let e = mesh_from_bytes("m.stl", &binary(&[T; 100], 100), false, 1000).unwrap_err();
        assert!(e.to_string().contains("budget"), "{e}");
        let e = mesh_from_bytes("f.obj", b"v 0 0 0\nf 1 2 3\n", true, 1 << 30).unwrap_err();
        assert!(e.to_string().contains("face index 2"), "{e}");
    }
}
