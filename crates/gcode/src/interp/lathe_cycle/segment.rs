//! One piece of a G7x profile: a straight or an arc in the (Z, X) plane, held as complex
//! numbers z + i·x as LinuxCNC's `interp_g7x.cc` does, so the cuts come out the same.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// A point or vector of the profile: `re` is Z, `im` is X.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub(super) struct C {
    pub(super) re: f64,
    pub(super) im: f64,
}

pub(super) const fn c(re: f64, im: f64) -> C {
    C { re, im }
}

/// The imaginary unit.
pub(super) const I: C = c(0.0, 1.0);

impl C {
    pub(super) fn conj(self) -> C {
        c(self.re, -self.im)
    }
    pub(super) fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    /// The squared magnitude (C++'s `std::norm`).
    pub(super) fn norm(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    pub(super) fn scale(self, k: f64) -> C {
        c(self.re * k, self.im * k)
    }
}

impl Add for C {
    type Output = C;
    fn add(self, o: C) -> C {
        c(self.re + o.re, self.im + o.im)
    }
}
impl AddAssign for C {
    fn add_assign(&mut self, o: C) {
        *self = *self + o;
    }
}
impl Sub for C {
    type Output = C;
    fn sub(self, o: C) -> C {
        c(self.re - o.re, self.im - o.im)
    }
}
impl Neg for C {
    type Output = C;
    fn neg(self) -> C {
        c(-self.re, -self.im)
    }
}
impl Mul for C {
    type Output = C;
    fn mul(self, o: C) -> C {
        c(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}
impl Div for C {
    type Output = C;
    fn div(self, o: C) -> C {
        let n = o.norm();
        let p = self * o.conj();
        c(p.re / n, p.im / n)
    }
}

pub(super) const TOLERANCE: f64 = 1e-6;

/// A move the cycle makes, in the turned profile's frame.
#[derive(Clone, Copy, Debug)]
pub(super) enum Move {
    Feed(C),
    Rapid(C),
    Arc { ccw: bool, center: C, end: C },
}

/// The shape of a piece; a corner finish is a piece of zero length until
/// [`Segment::finish_corner`] fits it between its neighbours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Shape {
    Straight,
    Round { ccw: bool, center: C },
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Segment {
    pub(super) start: C,
    pub(super) end: C,
    pub(super) shape: Shape,
    /// A fillet's radius or a chamfer's length, until it is fitted (fillets) — 0 otherwise.
    pub(super) finish: f64,
    pub(super) fillet: bool,
}

pub(super) type Geo<T> = Result<T, String>;

impl Segment {
    pub(super) fn straight(start: C, end: C) -> Segment {
        Segment {
            start,
            end,
            shape: Shape::Straight,
            finish: 0.0,
            fillet: false,
        }
    }
    pub(super) fn round(ccw: bool, start: C, center: C, end: C) -> Segment {
        Segment {
            start,
            end,
            shape: Shape::Round { ccw, center },
            finish: 0.0,
            fillet: false,
        }
    }
    pub(super) fn fillet(radius: f64, at: C) -> Segment {
        Segment {
            finish: radius,
            fillet: true,
            ..Segment::round(false, at, at, at)
        }
    }
    pub(super) fn chamfer(length: f64, at: C) -> Segment {
        Segment {
            finish: length,
            ..Segment::straight(at, at)
        }
    }

    /// The points along the line x = `x` where it meets this piece, in Z.
    pub(super) fn intersection_z(&self, x: f64, is: &mut Vec<f64>) {
        let (start, end) = (self.start, self.end);
        match self.shape {
            Shape::Straight => {
                if start.im.min(end.im) > x + TOLERANCE || start.im.max(end.im) < x - TOLERANCE {
                    return;
                }
                if (start - end).im.abs() < TOLERANCE {
                    is.push(start.re);
                    is.push(end.re);
                } else {
                    is.push((x - start.im) / (end.im - start.im) * (end.re - start.re) + start.re);
                }
            }
            Shape::Round { center, .. } => {
                let r = (start - center).abs();
                // (x − xc)² + s² = r²: s is the half chord along Z.
                let mut s = -(x - r - center.im) * (x + r - center.im);
                if s < -TOLERANCE {
                    return;
                }
                if s < 0.0 {
                    s = 0.0;
                }
                let s = s.sqrt();
                for p in [c(center.re + s, x), c(center.re - s, x)] {
                    if self.on_arc(p) {
                        is.push(p.re);
                    }
                }
            }
        }
    }

    fn on_arc(&self, p: C) -> bool {
        let (ccw, center) = match self.shape {
            Shape::Round { ccw, center } => (ccw, center),
            Shape::Straight => return false,
        };
        let a = ((self.start - center).conj() * (p - center)).im;
        let b = ((self.end - center).conj() * (p - center)).im;
        if ccw {
            a >= -TOLERANCE && b <= TOLERANCE
        } else {
            a <= TOLERANCE && b >= -TOLERANCE
        }
    }

    /// Follow the piece up (X growing); true when it does not climb from here.
    pub(super) fn climb(&self, location: &mut C, out: &mut Vec<Move>) -> Geo<bool> {
        match self.shape {
            Shape::Straight => {
                if self.end.im + TOLERANCE < self.start.im {
                    return Ok(true);
                }
                if (*location - self.start).abs() > TOLERANCE {
                    return Err("How did we get here?".into());
                }
                out.push(Move::Feed(self.end));
                *location = self.end;
                Ok(false)
            }
            Shape::Round { ccw: false, center } => {
                if location.re > center.re {
                    return Ok(true);
                }
                if (*location - self.end).abs() > 1e-3 {
                    out.push(Move::Arc {
                        ccw: false,
                        center,
                        end: self.end,
                    });
                }
                *location = self.end;
                Ok(false)
            }
            Shape::Round { ccw: true, center } => {
                if location.re < center.re {
                    return Ok(true);
                }
                let ep = self.top_or_end(center);
                if (*location - ep).abs() > 1e-3 {
                    out.push(Move::Arc {
                        ccw: true,
                        center,
                        end: ep,
                    });
                }
                *location = ep;
                Ok(true)
            }
        }
    }

    /// A G3 arc climbs only to its top (the point above its centre).
    fn top_or_end(&self, center: C) -> C {
        if self.end.re < center.re {
            c(center.re, center.im + (self.start - center).abs())
        } else {
            self.end
        }
    }

    /// Climb from where the line x = location.x meets the piece (after the roughing pass).
    pub(super) fn climb_only(&self, location: &mut C, out: &mut Vec<Move>) {
        match self.shape {
            Shape::Straight => {
                if self.end.im < self.start.im {
                    return;
                }
                let mut is = Vec::new();
                self.intersection_z(location.im, &mut is);
                let Some(&z) = is.first() else { return };
                location.re = z;
                out.push(Move::Feed(*location));
                out.push(Move::Feed(self.end));
                *location = self.end;
            }
            Shape::Round { ccw, center } => {
                let mut is = Vec::new();
                self.intersection_z(location.im, &mut is);
                if is.is_empty() {
                    return;
                }
                let ep = if ccw {
                    if is[0] < center.re {
                        return;
                    }
                    location.re = is[0];
                    self.top_or_end(center)
                } else {
                    if *is.last().unwrap() > center.re {
                        return;
                    }
                    location.re = *is.last().unwrap();
                    self.end
                };
                out.push(Move::Feed(*location));
                if (*location - ep).abs() > 1e-3 {
                    out.push(Move::Arc {
                        ccw,
                        center,
                        end: ep,
                    });
                }
                *location = ep;
            }
        }
    }

    /// Follow the piece down to the line x = `x`; true when it does not dive from here.
    pub(super) fn dive(
        &self,
        location: &mut C,
        x: f64,
        out: &mut Vec<Move>,
        fast: bool,
    ) -> Geo<bool> {
        let (start, end) = (self.start, self.end);
        match self.shape {
            Shape::Straight => {
                if start.im <= end.im + TOLERANCE {
                    return Ok(true);
                }
                let to = if x < end.im {
                    end
                } else {
                    let mut is = Vec::new();
                    self.intersection_z(x, &mut is);
                    match is.first() {
                        Some(&z) => c(z, x),
                        None => return Err("x too large in straight dive".into()),
                    }
                };
                out.push(if fast {
                    Move::Rapid(to)
                } else {
                    Move::Feed(to)
                });
                *location = to;
                Ok(false)
            }
            Shape::Round { ccw, center } => {
                if (*location - end).abs() < TOLERANCE || (*location - end).re <= TOLERANCE {
                    *location = end;
                    return Ok(false);
                }
                let mut is = Vec::new();
                self.intersection_z(x, &mut is);
                if is.is_empty() {
                    self.intersection_z(x - TOLERANCE, &mut is);
                }
                if ccw {
                    if location.re - TOLERANCE > center.re {
                        return Ok(true);
                    }
                    let to = match is.last() {
                        Some(&z) if z <= center.re => c(z, x),
                        _ => end,
                    };
                    out.push(Move::Arc {
                        ccw,
                        center,
                        end: to,
                    });
                    *location = to;
                } else {
                    if location.re <= center.re {
                        return Ok(true); // already climbing
                    }
                    match is.first() {
                        None => {
                            out.push(Move::Arc { ccw, center, end });
                            *location = end;
                        }
                        // Hit at the back side only: the pocket lowers x.
                        Some(&z) if z < center.re => {}
                        Some(&z) => {
                            let to = c(z, x);
                            out.push(Move::Arc {
                                ccw,
                                center,
                                end: to,
                            });
                            *location = to;
                        }
                    }
                }
                Ok(false)
            }
        }
    }

    pub(super) fn draw(&self) -> Move {
        match self.shape {
            Shape::Straight => Move::Feed(self.end),
            Shape::Round { ccw, center } => Move::Arc {
                ccw,
                center,
                end: self.end,
            },
        }
    }

    /// Move the piece `distance` sideways (to the left of its direction for a straight;
    /// away from the centre of a G3 arc).
    pub(super) fn offset(&mut self, distance: f64) {
        match self.shape {
            Shape::Straight => {
                let d = I * (self.start - self.end).scale(distance / (self.start - self.end).abs());
                self.start += d;
                self.end += d;
            }
            Shape::Round { ccw, center } => {
                let r = (self.start - center).abs();
                let factor = (r + if ccw { distance } else { -distance }) / r;
                self.start = (self.start - center).scale(factor) + center;
                self.end = (self.end - center).scale(factor) + center;
            }
        }
    }

    pub(super) fn radius(&self) -> f64 {
        match self.shape {
            Shape::Straight => (self.start - self.end).abs(),
            Shape::Round { center, .. } => (self.start - self.end)
                .abs()
                .min((self.start - center).abs()),
        }
    }

    pub(super) fn monotonic(&self) -> bool {
        match self.shape {
            Shape::Straight => (self.end - self.start).re <= 1e-3,
            Shape::Round { ccw, center } => {
                if self.finish != 0.0 {
                    return true;
                }
                let entry = (self.start - center).im;
                let exit = (self.end - center).im;
                let dz = (self.end - self.start).re;
                if ccw {
                    entry >= -1e-3 && exit >= -1e-3 && dz <= -1e-3
                } else {
                    entry <= 1e-3 && exit <= 1e-3 && dz <= -1e-3
                }
            }
        }
    }

    /// Apply `f` to every point, `mirror` when it reverses the turning sense.
    pub(super) fn map(&mut self, f: impl Fn(C) -> C, mirror: bool) {
        self.start = f(self.start);
        self.end = f(self.end);
        if let Shape::Round { ccw, center } = self.shape {
            self.shape = Shape::Round {
                ccw: ccw != mirror,
                center: f(center),
            };
        }
    }

    /// Fit this corner finish between `prev` and `next`, trimming them.
    pub(super) fn finish_corner(&mut self, prev: &mut Segment, next: &mut Segment) -> Geo<()> {
        if self.finish == 0.0 {
            return Ok(());
        }
        let attempt = |finish: f64| {
            let (mut p, mut n) = (*prev, *next);
            p.offset(finish);
            n.offset(finish);
            (p, n)
        };
        let (mut p, mut n) = attempt(self.finish);
        if (p.end - n.start).re > 1e-2 {
            self.finish = -self.finish;
            (p, n) = attempt(self.finish);
        }
        if (p.end - n.start).re > 1e-2 {
            return Err(format!(
                "Corner finish failed at ({},{})",
                prev.end.re, prev.end.im
            ));
        }
        intersect(&mut p, &mut n)?;
        let center = (p.end + n.start).scale(0.5);
        p.offset(-self.finish);
        n.offset(-self.finish);
        prev.end = p.end;
        self.start = p.end;
        next.start = n.start;
        self.end = n.start;
        if self.fillet {
            let ccw = (self.start - center).im > 0.0 || (self.end - center).im > 0.0;
            self.shape = Shape::Round { ccw, center };
            self.finish = 0.0;
        }
        Ok(())
    }

    pub(super) fn translate(&mut self, d: C) {
        self.map(|p| p + d, false);
    }
}

/// Move the end of `p` and the start of `n` to where the two pieces meet.
pub(super) fn intersect(p: &mut Segment, n: &mut Segment) -> Geo<()> {
    match (p.shape, n.shape) {
        (Shape::Straight, Shape::Straight) => {
            let rot = (n.start - n.end)
                .conj()
                .scale(1.0 / (n.start - n.end).abs());
            let ps = (p.start - n.end) * rot;
            let pe = (p.end - n.end) * rot;
            if (ps - pe).im == 0.0 {
                return Err("Cannot intersect parallel lines".into());
            }
            let f = ps.im / (ps - pe).im;
            let is = (ps + (pe - ps).scale(f)) / rot + n.end;
            n.start = is;
            p.end = is;
        }
        (Shape::Round { center: pc0, .. }, Shape::Straight) => {
            // An arc followed by a straight.
            if (n.start - p.end).abs() < TOLERANCE {
                return Ok(());
            }
            let rot = (n.start - n.end)
                .conj()
                .scale(1.0 / (n.start - n.end).abs());
            let pe = (p.end - n.end) * rot;
            let pc = (pc0 - n.end) * rot;
            let is = line_circle(pc, pe, rot, n.end, n.start);
            n.start = is;
            p.end = is;
        }
        (Shape::Straight, Shape::Round { center: nc0, .. }) => {
            // A straight followed by an arc.
            if (n.start - p.end).abs() < TOLERANCE {
                return Ok(());
            }
            let rot = (p.start - p.end)
                .conj()
                .scale(1.0 / (p.start - p.end).abs());
            let pe = (n.end - p.end) * rot;
            let pc = (nc0 - p.end) * rot;
            let is = line_circle(pc, pe, rot, p.end, n.start);
            n.start = is;
            p.end = is;
        }
        (Shape::Round { center: pc, .. }, Shape::Round { center: nc, .. }) => {
            // The triangle of the two centres and the meeting point: the law of cosines
            // gives the angle at n's centre.
            let a = (n.start - nc).abs();
            let b = (p.start - pc).abs();
            let cc = (nc - pc).abs();
            let cos_b = (cc * cc + a * a - b * b) / 2.0 / a / cc;
            let cos_b2 = (cos_b * cos_b).min(1.0);
            let rot = c(cos_b, (1.0 - cos_b2).sqrt());
            let is = rot * (pc - nc).scale(a / cc) + nc;
            p.end = is;
            n.start = is;
        }
    }
    Ok(())
}

/// In a frame where the line is the real axis through `origin`: the point of the circle
/// about `pc` through `pe` on the line, nearest `near` (back in the profile's frame).
fn line_circle(pc: C, pe: C, rot: C, origin: C, near: C) -> C {
    let b = ((pc - pe).norm() - pc.im * pc.im).max(0.0).sqrt();
    let s1 = c(pc.re + b, 0.0) / rot + origin;
    let s2 = c(pc.re - b, 0.0) / rot + origin;
    if (near - s1).abs() < (near - s2).abs() {
        s1
    } else {
        s2
    }
}
