//! The height map: a regular grid of probed surface heights (work Z, mm), bilinear between
//! the probed points, saved and read back as a small JSON file.

use serde::{Deserialize, Serialize};

/// Most points along one axis of a map: a 100 × 100 grid is already ten thousand probes.
pub const MAX_GRID: usize = 100;

/// The file's `format` tag.
const FORMAT: &str = "oficina-height-map";

/// Probed surface heights over a rectangle of the work XY plane.
///
/// `z` holds **absolute work Z** (the machine Z of each contact minus the work offset in
/// force while probing), so levelling adds `z(x, y)` to every programmed Z below the
/// clearance: a cut programmed at Z = −0.1 lands 0.1 mm below the surface wherever the
/// surface is. The work zero must not move between probing and cutting (no re-zeroing Z);
/// `wcs` names the coordinate system that was probed.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// Work X, Y of the first grid point (the smallest X and Y), mm.
    pub origin: [f64; 2],
    /// Distance between grid points along X and Y, mm (> 0).
    pub spacing: [f64; 2],
    /// Points along X (2 … [`MAX_GRID`]).
    pub nx: usize,
    /// Points along Y (2 … [`MAX_GRID`]).
    pub ny: usize,
    /// Heights, row by row from the smallest Y: `z[j * nx + i]` is at
    /// `origin + (i·spacing.x, j·spacing.y)`; work Z, mm.
    pub z: Vec<f64>,
    /// The work Z the probe started from at each point, mm: above every probed height.
    /// Levelling leaves alone moves that stay at or above it.
    pub clearance: f64,
    /// The work coordinate system active while probing (`G54` … `G59`), when known.
    pub wcs: Option<String>,
}

/// The JSON file (see [`HeightMap`]): `z` as `ny` rows of `nx` values.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct MapFile {
    format: String,
    version: u32,
    units: String,
    reference: String,
    origin: [f64; 2],
    spacing: [f64; 2],
    nx: usize,
    ny: usize,
    clearance: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    wcs: Option<String>,
    z: Vec<Vec<f64>>,
}

impl HeightMap {
    /// A map checked for shape and finite values: `z` must hold `nx·ny` heights, all below
    /// `clearance`.
    pub fn new(
        origin: [f64; 2],
        spacing: [f64; 2],
        nx: usize,
        ny: usize,
        z: Vec<f64>,
        clearance: f64,
    ) -> Result<HeightMap, String> {
        let map = HeightMap {
            origin,
            spacing,
            nx,
            ny,
            z,
            clearance,
            wcs: None,
        };
        map.check()?;
        Ok(map)
    }

    /// The map's shape and values are sound (what [`HeightMap::new`] and
    /// [`HeightMap::from_json`] ensure; a map built field by field is checked with this).
    pub fn check(&self) -> Result<(), String> {
        for (what, n) in [("nx", self.nx), ("ny", self.ny)] {
            if !(2..=MAX_GRID).contains(&n) {
                return Err(format!(
                    "height map: {what} = {n}: a map needs 2 to {MAX_GRID} points along each axis"
                ));
            }
        }
        if !self.origin.iter().all(|v| v.is_finite()) {
            return Err("height map: the origin must be finite".into());
        }
        if !self.spacing.iter().all(|v| v.is_finite() && *v > 0.0) {
            return Err(format!(
                "height map: spacing {:?} must be positive",
                self.spacing
            ));
        }
        if self.z.len() != self.nx * self.ny {
            return Err(format!(
                "height map: {} heights for a {} × {} grid",
                self.z.len(),
                self.nx,
                self.ny
            ));
        }
        if !self.clearance.is_finite() {
            return Err("height map: the clearance must be finite".into());
        }
        if let Some(k) = self.z.iter().position(|v| !v.is_finite()) {
            let (i, j) = (k % self.nx, k / self.nx);
            return Err(format!(
                "height map: the height at column {i}, row {j} is not a number"
            ));
        }
        if let Some(k) = self.z.iter().position(|v| *v >= self.clearance) {
            let (i, j) = (k % self.nx, k / self.nx);
            return Err(format!(
                "height map: the height {} at column {i}, row {j} is not below the clearance {}",
                self.z[k], self.clearance
            ));
        }
        Ok(())
    }

    /// The largest X and Y of the grid, mm.
    pub fn max_corner(&self) -> [f64; 2] {
        [
            self.origin[0] + (self.nx - 1) as f64 * self.spacing[0],
            self.origin[1] + (self.ny - 1) as f64 * self.spacing[1],
        ]
    }

    /// The probed height at grid point (`i`, `j`).
    pub fn at_node(&self, i: usize, j: usize) -> f64 {
        self.z[j * self.nx + i]
    }

    /// How far (`x`, `y`) lies outside the grid's rectangle, mm (0 inside).
    pub fn outside_by(&self, x: f64, y: f64) -> f64 {
        let [x1, y1] = self.max_corner();
        let dx = (self.origin[0] - x).max(x - x1).max(0.0);
        let dy = (self.origin[1] - y).max(y - y1).max(0.0);
        dx.hypot(dy)
    }

    /// The surface height at (`x`, `y`), bilinear in the grid cell holding the point; a
    /// point outside the grid takes the height at the nearest point of its edge.
    ///
    /// In the cell with corners z00 (i, j), z10 (i+1, j), z01 (i, j+1), z11 (i+1, j+1) and
    /// fractions u = (x − x_i)/dx, v = (y − y_j)/dy in [0, 1]:
    /// z = (1−u)(1−v)·z00 + u(1−v)·z10 + (1−u)v·z01 + uv·z11, which is exact on the
    /// corners and linear along every cell edge, so neighbouring cells agree on their edge.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let (i, u) = cell(x - self.origin[0], self.spacing[0], self.nx);
        let (j, v) = cell(y - self.origin[1], self.spacing[1], self.ny);
        let z00 = self.at_node(i, j);
        let z10 = self.at_node(i + 1, j);
        let z01 = self.at_node(i, j + 1);
        let z11 = self.at_node(i + 1, j + 1);
        (1.0 - u) * (1.0 - v) * z00 + u * (1.0 - v) * z10 + (1.0 - u) * v * z01 + u * v * z11
    }

    /// The lowest and highest probed heights.
    pub fn z_range(&self) -> (f64, f64) {
        self.z
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &z| {
                (lo.min(z), hi.max(z))
            })
    }

    /// The map as its JSON file.
    pub fn to_json(&self) -> String {
        let file = MapFile {
            format: FORMAT.into(),
            version: 1,
            units: "mm".into(),
            reference: "work-z".into(),
            origin: self.origin,
            spacing: self.spacing,
            nx: self.nx,
            ny: self.ny,
            clearance: self.clearance,
            wcs: self.wcs.clone(),
            z: self.z.chunks(self.nx).map(|r| r.to_vec()).collect(),
        };
        // A struct of numbers, strings and vectors always serialises.
        serde_json::to_string_pretty(&file).unwrap_or_default() + "\n"
    }

    /// Reads a map file; anything malformed is an error saying what. Files larger than a
    /// [`MAX_GRID`]² map could be are refused before parsing.
    pub fn from_json(text: &str) -> Result<HeightMap, String> {
        // 100 × 100 heights of ~25 characters each, with room for the rest.
        const MAX_BYTES: usize = MAX_GRID * MAX_GRID * 32 + 4096;
        if text.len() > MAX_BYTES {
            return Err(format!(
                "height map: {} bytes is more than a {MAX_GRID} × {MAX_GRID} map takes",
                text.len()
            ));
        }
        let f: MapFile =
            serde_json::from_str(text).map_err(|e| format!("height map: not a map file: {e}"))?;
        if f.format != FORMAT || f.version != 1 {
            return Err(format!(
                "height map: format {:?} version {}: expected {FORMAT:?} version 1",
                f.format, f.version
            ));
        }
        if f.units != "mm" || f.reference != "work-z" {
            return Err(format!(
                "height map: units {:?}, reference {:?}: expected \"mm\" and \"work-z\"",
                f.units, f.reference
            ));
        }
        if f.z.len() != f.ny || f.z.iter().any(|r| r.len() != f.nx) {
            return Err(format!(
                "height map: z must be {} rows of {} heights",
                f.ny, f.nx
            ));
        }
        let map = HeightMap {
            origin: f.origin,
            spacing: f.spacing,
            nx: f.nx,
            ny: f.ny,
            z: f.z.into_iter().flatten().collect(),
            clearance: f.clearance,
            wcs: f.wcs,
        };
        map.check()?;
        Ok(map)
    }
}

/// The cell index (0 … n−2) and the fraction within it (0 … 1) of offset `d` along an axis
/// of `n` points `step` apart; outside the axis, the end cell at fraction 0 or 1.
fn cell(d: f64, step: f64, n: usize) -> (usize, f64) {
    let t = (d / step).max(0.0).min((n - 1) as f64);
    let i = (t.floor() as usize).min(n - 2);
    (i, t - i as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 2 grid at (10, 20), 2 mm by 4 mm:
    /// row y=20: 0.0 1.0 3.0; row y=24: 2.0 2.0 -1.0.
    fn small() -> HeightMap {
        HeightMap::new(
            [10.0, 20.0],
            [2.0, 4.0],
            3,
            2,
            vec![0.0, 1.0, 3.0, 2.0, 2.0, -1.0],
            5.0,
        )
        .unwrap()
    }

    #[test]
    fn bilinear_matches_hand_computed_values() {
        let m = small();
        // Nodes are exact.
        assert_eq!(m.height(10.0, 20.0), 0.0);
        assert_eq!(m.height(14.0, 24.0), -1.0);
        assert_eq!(m.height(12.0, 24.0), 2.0);
        // Centre of the first cell: mean of 0, 1, 2, 2 = 1.25.
        assert!((m.height(11.0, 22.0) - 1.25).abs() < 1e-12);
        // (13, 21): cell 1, u = 0.5, v = 0.25:
        // 0.375·1 + 0.375·3 + 0.125·2 + 0.125·(−1) = 0.375 + 1.125 + 0.25 − 0.125 = 1.625.
        assert!((m.height(13.0, 21.0) - 1.625).abs() < 1e-12);
        // On the edge y = 20 between nodes: linear, 0.5 of the way from 1 to 3.
        assert!((m.height(13.0, 20.0) - 2.0).abs() < 1e-12);
        // Outside: the nearest edge point. (9, 19) → node (10, 20); (16, 22) → edge x = 14
        // at v = 0.5: (3 + −1)/2 = 1.
        assert_eq!(m.height(9.0, 19.0), 0.0);
        assert!((m.height(16.0, 22.0) - 1.0).abs() < 1e-12);
        assert_eq!(m.outside_by(16.0, 22.0), 2.0);
        assert_eq!(m.outside_by(12.0, 22.0), 0.0);
    }

    #[test]
    fn json_round_trip_and_malformed_files() {
        let mut m = small();
        m.wcs = Some("G54".into());
        let text = m.to_json();
        assert!(text.contains("\"reference\": \"work-z\""), "{text}");
        assert_eq!(HeightMap::from_json(&text).unwrap(), m);
        let bad = |t: &str| HeightMap::from_json(t).unwrap_err();
        assert!(bad("{").contains("not a map file"));
        assert!(bad(&text.replace("\"nx\": 3", "\"nx\": 4")).contains("rows of 4"));
        assert!(bad(&text.replace("\"version\": 1", "\"version\": 7")).contains("version"));
        assert!(
            bad(&text.replace("\"clearance\": 5.0", "\"clearance\": 2.5"))
                .contains("not below the clearance")
        );
        assert!(bad(&text.replace("\"units\": \"mm\"", "\"units\": \"in\"")).contains("units"));
        assert!(bad(&" ".repeat(400_000)).contains("bytes"));
        let neg = HeightMap::new([0.0; 2], [-1.0, 1.0], 2, 2, vec![0.0; 4], 5.0).unwrap_err();
        assert!(neg.contains("spacing"), "{neg}");
        assert!(bad(&text.replace("\"nx\"", "\"extra\": 1, \"nx\"")).contains("not a map file"));
    }

    #[test]
    fn grid_sizes_are_bounded() {
        let one = HeightMap::new([0.0; 2], [1.0; 2], 1, 1, vec![0.0], 5.0).unwrap_err();
        assert!(one.contains("2 to 100"), "{one}");
        let huge = HeightMap::new([0.0; 2], [1.0; 2], 10_000, 10_000, vec![], 5.0).unwrap_err();
        assert!(huge.contains("2 to 100"), "{huge}");
    }
}
