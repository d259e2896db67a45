//! Where to probe: a grid over a rectangle of the work plane (a program's extents plus a
//! margin, or a given one), visited in serpentine order, and the probing of it through any
//! [`SurfaceProbe`] into a [`HeightMap`].

use super::map::{HeightMap, MAX_GRID};

/// "Touch the surface at work (x, y) and say its work Z": a machine with a probe, or a
/// closure in tests.
pub trait SurfaceProbe {
    /// The work Z (mm) where the probe touched the surface above work (`x`, `y`) (mm).
    fn probe_at(&mut self, x: f64, y: f64) -> Result<f64, String>;
}

impl<F: FnMut(f64, f64) -> Result<f64, String>> SurfaceProbe for F {
    fn probe_at(&mut self, x: f64, y: f64) -> Result<f64, String> {
        self(x, y)
    }
}

/// How dense the grid is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GridSpec {
    /// This many points along X and Y (`5x5`).
    Count(usize, usize),
    /// Points at most this far apart, mm (`10` or `10mm`): the count along each axis is the
    /// smallest that keeps the spacing at or below it.
    Spacing(f64),
}

impl std::str::FromStr for GridSpec {
    type Err = String;
    /// `5x5` (points along X and Y) or `10` / `10mm` (largest spacing, mm).
    fn from_str(s: &str) -> Result<GridSpec, String> {
        let t = s.trim().to_ascii_lowercase();
        let bad = || {
            format!("grid {s:?}: expected points along X and Y such as 5x5, or a spacing in mm such as 10")
        };
        if let Some((a, b)) = t.split_once('x') {
            let nx: usize = a.trim().parse().map_err(|_| bad())?;
            let ny: usize = b.trim().parse().map_err(|_| bad())?;
            return Ok(GridSpec::Count(nx, ny));
        }
        let v: f64 = t.trim_end_matches("mm").trim().parse().map_err(|_| bad())?;
        Ok(GridSpec::Spacing(v))
    }
}

/// A rectangle of the work XY plane, mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Area {
    /// Smallest X and Y.
    pub min: [f64; 2],
    /// Largest X and Y.
    pub max: [f64; 2],
}

impl std::str::FromStr for Area {
    type Err = String;
    /// `X0,Y0,X1,Y1` in mm.
    fn from_str(s: &str) -> Result<Area, String> {
        let v: Vec<f64> = s
            .split(',')
            .map(|p| p.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("area {s:?}: expected X0,Y0,X1,Y1 in mm"))?;
        match v[..] {
            [x0, y0, x1, y1] => Ok(Area {
                min: [x0.min(x1), y0.min(y1)],
                max: [x0.max(x1), y0.max(y1)],
            }),
            _ => Err(format!("area {s:?}: expected four numbers X0,Y0,X1,Y1")),
        }
    }
}

/// The grid to probe: `nx` × `ny` points from `origin`, `spacing` apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeGrid {
    /// Work X, Y of the first point (smallest X and Y), mm.
    pub origin: [f64; 2],
    /// Distance between points, mm.
    pub spacing: [f64; 2],
    /// Points along X.
    pub nx: usize,
    /// Points along Y.
    pub ny: usize,
}

impl ProbeGrid {
    /// The grid over `area` grown by `margin` mm on every side. A degenerate side (a
    /// program that is one straight line) still gets two points `2·margin` apart, or 1 mm
    /// when the margin is 0.
    pub fn over(area: Area, margin: f64, spec: GridSpec) -> Result<ProbeGrid, String> {
        if !(margin.is_finite() && margin >= 0.0) {
            return Err(format!("margin {margin}: must be 0 or more, mm"));
        }
        if !area.min.iter().chain(&area.max).all(|v| v.is_finite()) {
            return Err("the area to probe is not finite".into());
        }
        let mut lo = [area.min[0] - margin, area.min[1] - margin];
        let mut hi = [area.max[0] + margin, area.max[1] + margin];
        for k in 0..2 {
            if hi[k] - lo[k] < 1e-6 {
                lo[k] -= 0.5;
                hi[k] += 0.5;
            }
        }
        let size = [hi[0] - lo[0], hi[1] - lo[1]];
        let (nx, ny) = match spec {
            GridSpec::Count(nx, ny) => (nx, ny),
            GridSpec::Spacing(s) => {
                if !(s.is_finite() && s > 0.0) {
                    return Err(format!("grid spacing {s}: must be more than 0 mm"));
                }
                // n points span n − 1 gaps of at most s: n = ⌈size / s⌉ + 1.
                let n = |len: f64| ((len / s).ceil() + 1.0).min(1e9) as usize;
                (n(size[0]), n(size[1]))
            }
        };
        for (axis, n) in [("X", nx), ("Y", ny)] {
            if !(2..=MAX_GRID).contains(&n) {
                return Err(format!(
                    "grid of {nx} × {ny} points: {n} along {axis}; a grid needs 2 to {MAX_GRID} points along each axis"
                ));
            }
        }
        Ok(ProbeGrid {
            origin: lo,
            spacing: [size[0] / (nx - 1) as f64, size[1] / (ny - 1) as f64],
            nx,
            ny,
        })
    }

    /// Every point as (i, j), row by row from the smallest Y, each row in the direction
    /// opposite to the one before (serpentine: no long travel back between rows).
    pub fn serpentine(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.ny).flat_map(move |j| {
            (0..self.nx).map(move |k| (if j % 2 == 0 { k } else { self.nx - 1 - k }, j))
        })
    }

    /// Work X, Y of point (i, j), mm.
    pub fn point(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin[0] + i as f64 * self.spacing[0],
            self.origin[1] + j as f64 * self.spacing[1],
        ]
    }

    /// Probes every point in serpentine order; `progress(done, total, x, y, z)` hears each
    /// contact. The first failing point stops the probing with its error and position.
    pub fn probe(
        &self,
        probe: &mut dyn SurfaceProbe,
        clearance: f64,
        progress: &mut dyn FnMut(usize, usize, f64, f64, f64),
    ) -> Result<HeightMap, String> {
        if !(2..=MAX_GRID).contains(&self.nx) || !(2..=MAX_GRID).contains(&self.ny) {
            return Err(format!(
                "grid of {} × {} points: a grid needs 2 to {MAX_GRID} points along each axis",
                self.nx, self.ny
            ));
        }
        let total = self.nx * self.ny;
        let mut z = vec![0.0; total];
        for (done, (i, j)) in self.serpentine().enumerate() {
            let [x, y] = self.point(i, j);
            let h = probe.probe_at(x, y).map_err(|e| {
                format!(
                    "probing point {} of {total} at X{x:.3} Y{y:.3}: {e}",
                    done + 1
                )
            })?;
            if !(h.is_finite() && h < clearance) {
                return Err(format!(
                    "probing point {} of {total} at X{x:.3} Y{y:.3}: contact at Z{h} is not below the clearance Z{clearance}",
                    done + 1
                ));
            }
            z[j * self.nx + i] = h;
            progress(done + 1, total, x, y, h);
        }
        HeightMap::new(self.origin, self.spacing, self.nx, self.ny, z, clearance)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_and_grids_cover_the_area_with_margin() {
        assert_eq!("5x4".parse::<GridSpec>().unwrap(), GridSpec::Count(5, 4));
        assert_eq!("10mm".parse::<GridSpec>().unwrap(), GridSpec::Spacing(10.0));
        assert!("5x".parse::<GridSpec>().is_err());
        let area: Area = "30,20,0,0".parse().unwrap();
        assert_eq!(area.min, [0.0, 0.0]);
        let g = ProbeGrid::over(area, 2.0, GridSpec::Count(5, 3)).unwrap();
        assert_eq!(g.origin, [-2.0, -2.0]);
        assert_eq!(g.spacing, [8.5, 12.0]);
        assert_eq!(g.point(4, 2), [32.0, 22.0]);
        // 34 mm at most 10 apart: 4 gaps, 5 points; 24 mm: 3 gaps, 4 points.
        let s = ProbeGrid::over(area, 2.0, GridSpec::Spacing(10.0)).unwrap();
        assert_eq!((s.nx, s.ny), (5, 4));
        assert!(s.spacing[0] <= 10.0 && s.spacing[1] <= 10.0);
    }

    #[test]
    fn bad_grids_are_refused_with_the_reason() {
        let area: Area = "0,0,10,10".parse().unwrap();
        let e = ProbeGrid::over(area, 0.0, GridSpec::Count(1, 1)).unwrap_err();
        assert!(e.contains("2 to 100"), "{e}");
        let e = ProbeGrid::over(area, 0.0, GridSpec::Count(10_000, 10_000)).unwrap_err();
        assert!(e.contains("2 to 100"), "{e}");
        let e = ProbeGrid::over(area, 0.0, GridSpec::Spacing(1e-9)).unwrap_err();
        assert!(e.contains("2 to 100"), "{e}");
        assert!(ProbeGrid::over(area, -1.0, GridSpec::Count(3, 3)).is_err());
        assert!(ProbeGrid::over(area, 0.0, GridSpec::Spacing(0.0)).is_err());
    }

    #[test]
    fn serpentine_order_and_probing_through_a_closure() {
        let area: Area = "0,0,2,1".parse().unwrap();
        let g = ProbeGrid::over(area, 0.0, GridSpec::Count(3, 2)).unwrap();
        let order: Vec<_> = g.serpentine().collect();
        assert_eq!(order, [(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)]);
        let mut visited = Vec::new();
        let mut probe = |x: f64, y: f64| {
            visited.push((x, y));
            Ok(0.1 * x - 0.2 * y)
        };
        let map = g.probe(&mut probe, 5.0, &mut |_, _, _, _, _| {}).unwrap();
        assert_eq!(visited[3], (2.0, 1.0));
        assert!((map.at_node(2, 1) - 0.0).abs() < 1e-12);
        assert!((map.at_node(1, 0) - 0.1).abs() < 1e-12);
        let mut failing = |x: f64, _y: f64| {
            if x > 1.5 {
                Err("no contact".to_string())
            } else {
                Ok(0.0)
            }
        };
        let e = g
            .probe(&mut failing, 5.0, &mut |_, _, _, _, _| {})
            .unwrap_err();
        assert!(
            e.contains("point 3 of 6 at X2.000 Y0.000: no contact"),
            "{e}"
        );
    }
}
