//! Every path from a point `x` to a point `y` by way of a smooth
//! dielectric ball: reflected off it, or refracted in and out with `k`
//! reflections inside (`Kind`). These are the specular manifolds of
//! Hanika et al. 2015 ("Manifold next event estimation"), solved here
//! exactly rather than by Newton steps from one seed.
//!
//! A ball is symmetric about the line through `x` and its centre, so such
//! a path lies in the plane of `x`, the centre and `y`: in that plane it is
//! fixed by one number, the signed angle of incidence θ where it first
//! meets the ball. The path passes through `y` where the last ray's
//! signed distance from `y`, g(θ), is zero. Inside a caustic several θ do
//! (up to three in the plane), so all roots are wanted: g is sampled on a
//! grid of θ (both kinds through the ball at once, `sweep.rs`), each
//! change of sign is refined (Brent's method), and where |g| dips between
//! grid points without changing sign — two roots within a step, at the
//! caustic's fold — its extremum is sought. Roots closer than that finds
//! are missed; the estimator stays unbiased because the BSDF-sampled path
//! a search misses keeps its full weight (`mod.rs`). θ rather than the angle α at `x`: near grazing, α
//! hardly moves while the path swings (g has a square-root edge in α).
//!
//! The same symmetry gives the Jacobian the estimator needs: turning the
//! first direction about the axis by dφ turns `y` about it by ρ_y dφ, and
//! changing α by dα moves the last ray across `y` by g′(α) dα. The solid
//! angle at `x` per unit area at `y` across the last ray is therefore
//! dω/dA⊥ = sin|α| / (|g′(α)| ρ_y).

use std::cell::{Cell, OnceCell};

use super::sweep::{Setting, Swept, GRID, STEPS};
use crate::math::Vec3;

/// The most paths of one kind [`Ball::paths`] returns.
pub const MAX_PATHS: usize = 4;

/// How a path crosses the ball.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Reflected off its outside.
    Reflected,
    /// Refracted in, reflected inside this many times, refracted out.
    Through(u8),
}

impl Kind {
    /// The kinds searched: the reflection, and through the ball with up
    /// to three reflections inside. Those with two and three carry F² and
    /// F³ of the light (under 0.2 % at normal incidence for glass), but
    /// BSDF sampling finds them as rarely, and each find, unweighed,
    /// carries the lamp's whole radiance: in `glass-and-metals.xml` they
    /// were its brightest fireflies.
    pub const SEARCHED: [Kind; 5] = [
        Kind::Reflected,
        Kind::Through(0),
        Kind::Through(1),
        Kind::Through(2),
        Kind::Through(3),
    ];

    /// The segments of a path of this kind from a vertex by way of the
    /// ball to the next vertex.
    pub fn segments(self) -> i32 {
        match self {
            Kind::Reflected => 2,
            Kind::Through(k) => 3 + k as i32,
        }
    }

    /// The least and greatest angles a path of this kind turns by, for
    /// index ratio `eta` > 1: a reflection π − 2θ; straight through
    /// D₀ = 2(θ − θ_t), at most 2(π/2 − θ_c); with one reflection inside
    /// D₁ = π + 2θ − 4θ_t, at least at the rainbow's angle, cos²θ =
    /// (η² − 1)/3 (Descartes; e.g. Nussenzveig 1977). Wider where unsure.
    pub fn deviations(self, eta: f64) -> (f64, f64) {
        use std::f64::consts::PI;
        if eta.is_nan() || eta <= 1.0 {
            return (0.0, PI);
        }
        match self {
            Kind::Reflected => (0.0, PI),
            Kind::Through(0) => (0.0, PI - 2.0 * (1.0 / eta).asin()),
            Kind::Through(1) => {
                let cos2 = ((eta * eta - 1.0) / 3.0).clamp(0.0, 1.0);
                let theta = cos2.sqrt().acos();
                let theta_t = (theta.sin() / eta).asin();
                let least = PI + 2.0 * theta - 4.0 * theta_t;
                ((least - 1e-9).min(PI), PI)
            }
            Kind::Through(_) => (0.0, PI),
        }
    }

    /// The interfaces that reflect and that transmit on the way.
    pub fn events(self) -> (u8, u8) {
        match self {
            Kind::Reflected => (1, 0),
            Kind::Through(k) => (k, 2),
        }
    }
}

/// A smooth dielectric ball: interior over exterior index `eta`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    pub center: Vec3,
    pub radius: f32,
    pub eta: f32,
    /// Each searched kind's least and greatest turn
    /// ([`Kind::deviations`]), once rather than per search.
    turns: [(f64, f64); Kind::SEARCHED.len()],
}

/// One path `x` → `entry` → … → `exit` → `y` by way of the ball.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refracted {
    /// The unit direction from `x` to `entry`.
    pub dir: Vec3,
    pub entry: Vec3,
    /// Where it is first reflected inside (`exit` when it is not).
    pub mid: Vec3,
    /// Where it leaves the ball (`entry` for a reflection).
    pub exit: Vec3,
    /// The unit direction from `exit` towards `y`.
    pub out: Vec3,
    /// The cosine of incidence at `entry`. Every interface of the path
    /// meets it at this angle outside or at its refracted angle inside,
    /// so each reflects the same Fresnel fraction F.
    pub cos_in: f32,
    /// dω/dA⊥: solid angle at `x` per unit area at `y` across `out`.
    pub spread: f32,
}

/// The paths found.
#[derive(Debug, Clone, Copy)]
pub struct Paths {
    pub list: [Option<Refracted>; MAX_PATHS],
}

impl Paths {
    pub fn iter(&self) -> impl Iterator<Item = &Refracted> {
        self.list.iter().flatten()
    }
}

/// A 2-vector in the plane of the path.
type V2 = (f64, f64);

fn dot(a: V2, b: V2) -> f64 {
    a.0 * b.0 + a.1 * b.1
}

fn cross(a: V2, b: V2) -> f64 {
    a.0 * b.1 - a.1 * b.0
}

fn add(a: V2, b: V2, s: f64) -> V2 {
    (a.0 + b.0 * s, a.1 + b.1 * s)
}

/// The ball in the plane of a path: `x` at (dx, 0), the centre at the
/// origin, `y` at `y` with y.1 ≥ 0.
struct Plane {
    dx: f64,
    y: V2,
    r: f64,
    eta: f64,
    kind: Kind,
    /// 1/r, 1/dx and 1/η: no step divides.
    inv_r: f64,
    inv_dx: f64,
    inv_eta: f64,
    /// How far `x` and `y` lie from the centre, together.
    scale: f64,
}

/// Where the ray leaving `x` that meets the ball at θ enters and leaves.
struct Trace {
    entry: V2,
    mid: V2,
    exit: V2,
    out: V2,
}

impl Plane {
    /// sin α and cos α of the ray from `x` meeting the ball at incidence
    /// sin θ = `s` (its impact parameter is r sin θ).
    fn alpha(&self, s: f64) -> (f64, f64) {
        let sin_a = self.r * s * self.inv_dx;
        (sin_a, (1.0 - sin_a * sin_a).sqrt())
    }

    /// The path meeting the ball at incidence (sin θ, cos θ) = (`s`, `c`),
    /// cos θ ≥ 0.
    fn trace(&self, s: f64, c: f64) -> Trace {
        let (r, eta, inv_r, inv_eta) = (self.r, self.eta, self.inv_r, self.inv_eta);
        let (sin_a, cos_a) = self.alpha(s);
        let d = (-cos_a, sin_a);
        // |x + t d|² = r² with x·d = −dx cos α: the near root, whose
        // half-width √(r² − dx² sin²α) is r cos θ.
        let entry = add((self.dx, 0.0), d, self.dx * cos_a - r * c);
        let n1 = (entry.0 * inv_r, entry.1 * inv_r);
        let Kind::Through(k) = self.kind else {
            let out = add(d, n1, 2.0 * c);
            return Trace {
                entry,
                mid: entry,
                exit: entry,
                out,
            };
        };
        // Snell's law in: d1 = d/η + (cos θ/η − cos θ_t) n.
        let cos_t = (1.0 - s * s * inv_eta * inv_eta).sqrt();
        let d1 = add((d.0 * inv_eta, d.1 * inv_eta), n1, c * inv_eta - cos_t);
        // Chords: |p + t d1| = r again at t = −2 p·d1; a reflection
        // inside turns d1 about the normal there.
        let mut p = add(entry, d1, -2.0 * dot(entry, d1));
        let mid = p;
        let mut d1 = d1;
        for _ in 0..k {
            let n = (p.0 * inv_r, p.1 * inv_r);
            d1 = add(d1, n, -2.0 * dot(d1, n));
            p = add(p, d1, -2.0 * dot(p, d1));
        }
        let n2 = (p.0 * inv_r, p.1 * inv_r);
        // Snell's law out, from the refracted angle back to θ.
        let out = add((d1.0 * eta, d1.1 * eta), n2, c - eta * cos_t);
        Trace {
            entry,
            mid,
            exit: p,
            out,
        }
    }

    /// g: the signed distance of `y` from the last ray, and whether `y`
    /// lies ahead on it.
    fn miss(&self, s: f64, c: f64) -> (f64, bool) {
        self.miss_of(&self.trace(s, c))
    }

    /// g and whether `y` lies ahead, for the path traced `t`.
    fn miss_of(&self, t: &Trace) -> (f64, bool) {
        let to_y = (self.y.0 - t.exit.0, self.y.1 - t.exit.1);
        (cross(t.out, to_y), dot(t.out, to_y) > 0.0)
    }

    /// g at sin θ = `s`.
    fn miss_sin(&self, s: f64) -> f64 {
        self.miss(s, (1.0 - s * s).max(0.0).sqrt()).0
    }

    /// The root of g in sin θ ∈ [a, b], where g changes sign: Brent's
    /// method (inverse quadratic steps, bisection where they stray;
    /// Brent 1973, ch. 4), in sin θ so that no step needs a sine: 5
    /// evaluations per reflection found, where the Illinois method took 7.
    fn refine(&self, (mut a, mut fa): V2, (mut b, mut fb): V2) -> f64 {
        // Within a nanometre of `y` in a scene of metres, or 1e-10 in
        // sin θ: far below what f32 directions resolve.
        let (tol_g, tol_s) = (1e-9 * self.scale, 1e-10);
        let (mut c, mut fc) = (a, fa);
        let mut step = b - a;
        let mut last = step;
        for _ in 0..60 {
            if (fb < 0.0) == (fc < 0.0) {
                (c, fc) = (a, fa);
                step = b - a;
                last = step;
            }
            // b, the best so far; c across the root from it.
            if fc.abs() < fb.abs() {
                (a, fa) = (b, fb);
                (b, fb) = (c, fc);
                (c, fc) = (a, fa);
            }
            let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol_s;
            let half = 0.5 * (c - b);
            if half.abs() <= tol || fb.abs() <= tol_g {
                return b;
            }
            if last.abs() >= tol && fa.abs() > fb.abs() {
                // Interpolate: secant from two points, inverse quadratic
                // from three.
                let sb = fb / fa;
                let (mut p, mut q) = if a == c {
                    (2.0 * half * sb, 1.0 - sb)
                } else {
                    let (qa, rb) = (fa / fc, fb / fc);
                    (
                        sb * (2.0 * half * qa * (qa - rb) - (b - a) * (rb - 1.0)),
                        (qa - 1.0) * (rb - 1.0) * (sb - 1.0),
                    )
                };
                if p > 0.0 {
                    q = -q;
                }
                p = p.abs();
                if 2.0 * p < (3.0 * half * q - (tol * q).abs()).min((last * q).abs()) {
                    last = step;
                    step = p / q;
                } else {
                    step = half;
                    last = step;
                }
            } else {
                step = half;
                last = step;
            }
            (a, fa) = (b, fb);
            b += if step.abs() > tol {
                step
            } else {
                tol.copysign(half)
            };
            fb = self.miss_sin(b);
        }
        b
    }

    /// Where g, of one sign at the three points `a` < `b` < `c` and
    /// least in magnitude at `b`, takes the other sign: the extremum
    /// between them sought by successive parabolas (golden steps where a
    /// parabola strays), until it crosses zero or its bracket is below
    /// what f32 directions resolve. `None` when it does not cross.
    fn fold(&self, a: V2, b: V2, c: V2) -> Option<f64> {
        let sign = b.1.signum();
        let h = |p: V2| (p.0, p.1 * sign);
        let (mut a, mut b, mut c) = (h(a), h(b), h(c));
        for _ in 0..16 {
            if c.0 - a.0 <= 1e-9 {
                break;
            }
            let (p, q) = ((b.0 - a.0) * (b.1 - c.1), (b.0 - c.0) * (b.1 - a.1));
            let vertex = b.0 - 0.5 * ((b.0 - a.0) * p - (b.0 - c.0) * q) / (p - q);
            let tol = 1e-3 * (c.0 - a.0);
            // Else a golden-section step, (3 − √5)/2 into the wider side.
            let u = if vertex > a.0 + tol && vertex < c.0 - tol && (vertex - b.0).abs() > tol {
                vertex
            } else if b.0 - a.0 > c.0 - b.0 {
                b.0 - 0.381_966 * (b.0 - a.0)
            } else {
                b.0 + 0.381_966 * (c.0 - b.0)
            };
            let hu = self.miss_sin(u) * sign;
            if hu < 0.0 {
                return Some(u);
            }
            let m = (u, hu);
            (a, b, c) = match (hu < b.1, u < b.0) {
                (true, true) => (a, m, b),
                (true, false) => (b, m, c),
                (false, true) => (m, b, c),
                (false, false) => (a, b, m),
            };
        }
        None
    }

    /// sin θ where the ball's normal points along `v`, or just short of
    /// 1 where `x` cannot see that point.
    fn facing(&self, v: V2) -> f64 {
        let len = dot(v, v).sqrt();
        let n = (v.0 / len, v.1 / len);
        let v = (self.dx - n.0 * self.r, -n.1 * self.r);
        let v_len = dot(v, v).sqrt();
        if dot(n, v) <= 0.0 {
            1.0 - 1e-12
        } else {
            cross(v, n).abs() / v_len
        }
    }

    /// dg/dα at (sin θ, cos θ) = (`s`, `c`), where g is `g`: dg/dθ by a
    /// forward difference over dα/dθ = r cos θ / (dx cos α).
    fn slope(&self, s: f64, c: f64, g: f64) -> f64 {
        // A step of 1e-6 in θ, taken in sin θ: dθ = ds / cos θ. Its
        // error, h g″/2g′, is far below f32's but at a fold, where the
        // Jacobian is unbounded anyway.
        let h = 1e-6 * c;
        let da = self.r * c / (self.dx * self.alpha(s).1);
        (self.miss_sin(s + h) - g) / h * c / da
    }
}

fn to64(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn scale3(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

impl Ball {
    pub fn new(center: Vec3, radius: f32, eta: f32) -> Self {
        Self {
            center,
            radius,
            eta,
            turns: Kind::SEARCHED.map(|k| k.deviations(eta as f64)),
        }
    }

    /// Every path of `kind` from `x` by way of the ball to `y` (both
    /// outside it) that the search finds.
    pub fn paths(&self, kind: Kind, x: Vec3, y: Vec3) -> Paths {
        self.search(x, y).map_or(NONE, |s| s.paths(kind))
    }

    /// The cosine at which the ray from `x` (outside) along `dir` meets
    /// the ball first, if it does.
    pub fn entry_cos(&self, x: Vec3, dir: Vec3) -> Option<f32> {
        // In f64: near grazing the cosine is the root of a difference of
        // nearly equal squares.
        let d = to64(dir);
        let d = scale3(d, 1.0 / dot3(d, d).sqrt());
        let o = sub3(to64(x), to64(self.center));
        let r = self.radius as f64;
        let b = dot3(o, d);
        let disc = b * b - (dot3(o, o) - r * r);
        if !(disc > 0.0 && b < 0.0) {
            return None;
        }
        // The cosine at the nearer meeting, −d · (o + t d) / r with
        // t = −b − √disc.
        Some(((disc.sqrt()) / r).clamp(0.0, 1.0) as f32)
    }

    /// The plane of `x`, the centre and `y`, to search for paths of each
    /// kind in; `None` when there is none (a point inside the ball, or
    /// `y` on the axis, where every turn about it is a path: a set of no
    /// area).
    pub fn search(&self, x: Vec3, y: Vec3) -> Option<Search<'_>> {
        let c = to64(self.center);
        let r = self.radius as f64;
        let (xc, yc) = (sub3(to64(x), c), sub3(to64(y), c));
        let dx = dot3(xc, xc).sqrt();
        let dy = dot3(yc, yc).sqrt();
        if !(dx > r * (1.0 + 1e-6) && dy > r * (1.0 + 1e-6)) {
            return None;
        }
        // The plane's axes: e1 from the centre to x, e2 towards y.
        let e1 = scale3(xc, 1.0 / dx);
        let along = dot3(yc, e1);
        let perp = sub3(yc, scale3(e1, along));
        let rho = dot3(perp, perp).sqrt();
        if rho <= 1e-9 * dy {
            return None;
        }
        Some(Search {
            ball: self,
            e1,
            e2: scale3(perp, 1.0 / rho),
            dx,
            dy,
            along,
            rho,
            cone: Cell::new(None),
            swept: OnceCell::new(),
        })
    }
}

/// No paths.
const NONE: Paths = Paths {
    list: [None; MAX_PATHS],
};

/// The plane of a search: `x` at (dx, 0) on axis `e1` from the centre,
/// `y` at (along, ρ) with `e2`.
pub struct Search<'b> {
    ball: &'b Ball,
    e1: [f64; 3],
    e2: [f64; 3],
    dx: f64,
    dy: f64,
    along: f64,
    rho: f64,
    /// The angle from x → centre to centre → y, and how far a path's
    /// first and last directions can stray from those (the ball's half
    /// angles seen from x and from y), once asked for.
    cone: Cell<Option<(f64, f64)>>,
    /// The grid of both kinds through the ball, once for both.
    swept: OnceCell<Swept>,
}

impl Search<'_> {
    /// Whether a path can turn by an angle in [`lo`, `hi`] on its way:
    /// it turns from its first direction to its last by the kind's
    /// deviation, and those lie within the ball's cones seen from x and
    /// from y about the directions x → centre and centre → y.
    fn turns(&self, lo: f64, hi: f64) -> bool {
        let (turn, slack) = self.cone.get().unwrap_or_else(|| {
            let r = self.ball.radius as f64;
            let turn = (-self.along / self.dy).clamp(-1.0, 1.0).acos();
            let cone = (turn, (r / self.dx).asin() + (r / self.dy).asin());
            self.cone.set(Some(cone));
            cone
        });
        turn + slack >= lo && turn - slack <= hi
    }

    /// Every path of `kind` the search finds.
    pub fn paths(&self, kind: Kind) -> Paths {
        let mut found = NONE;
        let (r, eta) = (self.ball.radius as f64, self.ball.eta as f64);
        let (dx, dy) = (self.dx, self.dy);
        // Only the kinds searched: the estimator runs for no other.
        let Some(i) = Kind::SEARCHED.iter().position(|&k| k == kind) else {
            return found;
        };
        // Which way the light can turn (a reflection, any way).
        let (lo, hi) = self.ball.turns[i];
        if (lo > 0.0 || hi < std::f64::consts::PI) && !self.turns(lo, hi) {
            return found;
        }
        let plane = self.plane(kind);
        let world = |v: V2| self.world(v);
        let at = |v: V2| world(v) + self.ball.center;
        let mut n = 0;
        let mut keep = |lo: (f64, f64, bool), hi: (f64, f64, bool)| {
            if (lo.1 < 0.0) != (hi.1 < 0.0) && (lo.2 || hi.2) && n < MAX_PATHS {
                let root = plane.refine((lo.0, lo.1), (hi.0, hi.1));
                if let Some(p) = path_at(&plane, root, &world, &at) {
                    found.list[n] = Some(p);
                    n += 1;
                }
            }
        };
        let at_sin = |s: f64| {
            let (g, ahead) = plane.miss(s, (1.0 - s * s).max(0.0).sqrt());
            (s, g, ahead)
        };
        if kind == Kind::Reflected {
            // A convex mirror reflects x to y at one point, whose normal
            // lies between the directions to x (θ = 0) and to y; for far
            // points it halves the angle between them, which brackets it
            // tightly first.
            let edge = plane.facing(plane.y);
            let half = plane.facing((dy + self.along, self.rho)).min(edge);
            let (a, b) = (at_sin(0.8 * half), at_sin((1.2 * half).min(edge)));
            if (a.1 < 0.0) != (b.1 < 0.0) {
                keep(a, b);
            } else {
                keep(at_sin(0.0), at_sin(edge));
            }
            return found;
        }
        // Every kind through the ball searched is swept.
        let Kind::Through(k) = kind else {
            return found;
        };
        let swept = self.swept.get_or_init(|| {
            let y = plane.y;
            Setting { dx, y, r, eta }.sweep()
        });
        let k = k as usize;
        let g = std::array::from_fn(|i| (GRID[i].0, swept.g[k][i], swept.ahead[k][i]));
        Self::roots(&plane, g, &mut keep);
        found
    }

    /// The search's plane for paths of `kind`.
    fn plane(&self, kind: Kind) -> Plane {
        let (r, eta) = (self.ball.radius as f64, self.ball.eta as f64);
        Plane {
            dx: self.dx,
            y: (self.along, self.rho),
            r,
            eta,
            kind,
            inv_r: 1.0 / r,
            inv_dx: 1.0 / self.dx,
            inv_eta: 1.0 / eta,
            scale: self.dx + self.dy,
        }
    }

    /// A vector of the plane in the world, about the centre.
    fn world(&self, v: V2) -> Vec3 {
        let (e1, e2) = (self.e1, self.e2);
        Vec3::new(
            (e1[0] * v.0 + e2[0] * v.1) as f32,
            (e1[1] * v.0 + e2[1] * v.1) as f32,
            (e1[2] * v.0 + e2[2] * v.1) as f32,
        )
    }

    /// The path of `kind` that leaves `x` along `dir`, as a ray traced
    /// from `y` through the ball found it: the root of g at that angle,
    /// refined from a bracket about it, rather than every root searched
    /// for. `None` where none lies within 1e-3 in sin θ.
    pub fn path_along(&self, kind: Kind, dir: Vec3) -> Option<Refracted> {
        let plane = self.plane(kind);
        let e2 = self.e2;
        let sin_a = dir.x as f64 * e2[0] + dir.y as f64 * e2[1] + dir.z as f64 * e2[2];
        let s0 = sin_a * self.dx / plane.r;
        let at_sin = |s: f64| (s, plane.miss_sin(s.clamp(-1.0, 1.0)));
        let mut reach = 1e-6;
        while reach <= 1e-3 {
            let (a, b) = (at_sin(s0 - reach), at_sin(s0 + reach));
            if (a.1 < 0.0) != (b.1 < 0.0) {
                let root = plane.refine(a, b);
                let world = |v: V2| self.world(v);
                let at = |v: V2| world(v) + self.ball.center;
                return path_at(&plane, root, &world, &at);
            }
            reach *= 10.0;
        }
        None
    }

    /// The brackets of g's roots about the grid's points `g` (sin θ, g,
    /// whether `y` is ahead), each handed to `keep`.
    fn roots(
        plane: &Plane,
        g: [(f64, f64, bool); STEPS + 1],
        keep: &mut impl FnMut((f64, f64, bool), (f64, f64, bool)),
    ) {
        let at_sin = |s: f64| {
            let (g, ahead) = plane.miss(s, (1.0 - s * s).max(0.0).sqrt());
            (s, g, ahead)
        };
        for k in 0..STEPS {
            keep(g[k], g[k + 1]);
        }
        // At the caustic's fold two roots lie within a step: no change of
        // sign between grid points, but |g| dips between its neighbours.
        // Where it does, the least of g there is sought, and the roots on
        // either side of it refined if it crosses zero.
        for k in 1..STEPS {
            let (a, b, c) = (g[k - 1], g[k], g[k + 1]);
            let same = (a.1 < 0.0) == (b.1 < 0.0) && (b.1 < 0.0) == (c.1 < 0.0);
            if !same || b.1.abs() >= a.1.abs() || b.1.abs() >= c.1.abs() {
                continue;
            }
            if let Some(m) = plane.fold((a.0, a.1), (b.0, b.1), (c.0, c.1)) {
                let m = at_sin(m);
                let (lo, hi) = if m.0 < b.0 { (a, b) } else { (b, c) };
                keep(lo, m);
                keep(m, hi);
            }
        }
    }
}

/// The path at root sin θ = `s` of `plane`, with its Jacobian; `None`
/// when `y` lies behind the last ray or the root is degenerate.
fn path_at(
    plane: &Plane,
    s: f64,
    world: &impl Fn(V2) -> Vec3,
    at: &impl Fn(V2) -> Vec3,
) -> Option<Refracted> {
    let c = (1.0 - s * s).max(0.0).sqrt();
    let t = plane.trace(s, c);
    let (g, ahead) = plane.miss_of(&t);
    let slope = plane.slope(s, c, g).abs();
    if !ahead || slope.is_nan() || slope <= 0.0 || c <= 0.0 {
        return None;
    }
    let (sin_a, cos_a) = plane.alpha(s);
    let spread = sin_a.abs() / (slope * plane.y.1);
    Some(Refracted {
        dir: world((-cos_a, sin_a)),
        entry: at(t.entry),
        mid: at(t.mid),
        exit: at(t.exit),
        out: world(t.out).normalize(),
        cos_in: c as f32,
        spread: spread as f32,
    })
    .filter(|p| p.spread.is_finite())
}

#[cfg(test)]
mod tests {
    use super::super::sweep::{Setting, THROUGH};
    use super::*;
    use crate::math::Frame;
    use crate::sampling::splitmix::SplitMix;

    type D3 = [f64; 3];

    fn unit(a: D3) -> D3 {
        scale3(a, 1.0 / dot3(a, a).sqrt())
    }

    fn add3(a: D3, b: D3, s: f64) -> D3 {
        [a[0] + b[0] * s, a[1] + b[1] * s, a[2] + b[2] * s]
    }

    /// Snell's law in three dimensions, written apart from the plane's:
    /// `d` refracted at unit normal `n` (facing against `d`) from index
    /// ratio `eta` = n_from / n_to.
    fn refract(d: D3, n: D3, eta: f64) -> D3 {
        let cos_i = -dot3(d, n);
        let cos_t = (1.0 - eta * eta * (1.0 - cos_i * cos_i)).sqrt();
        add3(scale3(d, eta), n, eta * cos_i - cos_t)
    }

    /// The ray from `x` along `d` by way of `ball` as `kind` says: the
    /// exit point and direction, traced in 3D.
    fn through(ball: &Ball, kind: Kind, x: D3, d: D3) -> Option<(D3, D3)> {
        // A unit direction: these steps assume one, and each reflection
        // inside magnifies an f32 direction's error in its length.
        let d = unit(d);
        let c = to64(ball.center);
        let r = ball.radius as f64;
        let o = sub3(x, c);
        let b = dot3(o, d);
        let disc = b * b - (dot3(o, o) - r * r);
        if disc <= 0.0 {
            return None;
        }
        let entry = add3(x, d, -b - disc.sqrt());
        let n1 = scale3(sub3(entry, c), 1.0 / r);
        let Kind::Through(k) = kind else {
            return Some((entry, add3(d, n1, -2.0 * dot3(d, n1))));
        };
        let mut d1 = refract(d, n1, 1.0 / ball.eta as f64);
        let mut p = entry;
        for i in 0..=k {
            let o1 = sub3(p, c);
            p = add3(p, d1, -2.0 * dot3(o1, d1));
            if i < k {
                let n = scale3(sub3(p, c), 1.0 / r);
                d1 = add3(d1, n, -2.0 * dot3(d1, n));
            }
        }
        let n2 = scale3(sub3(p, c), 1.0 / r);
        let out = refract(d1, scale3(n2, -1.0), ball.eta as f64);
        Some((p, unit(out)))
    }

    /// Two unit vectors across `d` and each other (its frame's tangents).
    fn across(d: Vec3) -> (D3, D3) {
        let f = Frame::from_normal(d.normalize());
        (to64(f.s), to64(f.t))
    }

    /// Where the ray (o, d) meets the plane through `q` across `n`.
    fn on_plane(o: D3, d: D3, q: D3, n: D3) -> D3 {
        add3(o, d, dot3(sub3(q, o), n) / dot3(d, n))
    }

    static BALL: std::sync::LazyLock<Ball> =
        std::sync::LazyLock::new(|| Ball::new(Vec3::new(0.0, 0.25, 0.0), 0.25, 1.5046));

    fn random_point(rng: &mut SplitMix, lo: f64, hi: f64) -> Vec3 {
        let mut v = || (lo + (hi - lo) * rng.next_f32() as f64) as f32;
        Vec3::new(v(), v(), v())
    }

    /// A ray's first meeting with the ball, computed from the ray alone
    /// (for a path traced where the search found none), is where the
    /// search's paths enter: the same cosine; and rays that miss the ball
    /// or leave it behind meet none.
    #[test]
    fn a_rays_entry_cosine_is_the_searchs() {
        let mut rng = SplitMix(7);
        let mut checked = 0;
        while checked < 200 {
            let x = random_point(&mut rng, -1.0, 1.0);
            let y = random_point(&mut rng, -1.0, 1.0) + Vec3::new(0.0, 1.5, 0.0);
            for kind in Kind::SEARCHED {
                for p in BALL.paths(kind, x, y).iter() {
                    let cos = BALL.entry_cos(x, p.dir).expect("the path meets the ball");
                    assert!(
                        (cos - p.cos_in).abs() < 1e-4,
                        "{kind:?}: {cos} against {}",
                        p.cos_in
                    );
                    checked += 1;
                }
            }
        }
        let x = Vec3::new(1.0, 0.25, 0.0);
        assert!(BALL.entry_cos(x, Vec3::new(1.0, 0.0, 0.0)).is_none());
        assert!(BALL.entry_cos(x, Vec3::new(-1.0, 1.0, 0.0)).is_none());
        let head_on = BALL.entry_cos(x, Vec3::new(-1.0, 0.0, 0.0)).unwrap();
        assert!((head_on - 1.0).abs() < 1e-6);
    }

    /// Each path found leaves `x` along its direction, refracts through
    /// the ball by Snell's law traced in 3D, and passes through `y`.
    #[test]
    fn every_path_found_refracts_through_the_ball_to_its_end() {
        let mut rng = SplitMix(7);
        let mut checked = 0;
        for _ in 0..4000 {
            let x = random_point(&mut rng, -1.5, 1.5);
            let y = random_point(&mut rng, -1.5, 1.5);
            // Near grazing, the f32 direction's rounding alone moves the
            // exit ray by more (dθ/dα grows as 1/cos θ, and more so with
            // a reflection inside).
            for kind in Kind::SEARCHED {
                for p in BALL.paths(kind, x, y).iter().filter(|p| p.cos_in > 0.5) {
                    let (exit, out) = through(&BALL, kind, to64(x), to64(p.dir)).expect("meets");
                    let to_y = sub3(to64(y), exit);
                    let along = dot3(to_y, out);
                    let miss = sub3(to_y, scale3(out, along));
                    assert!(along > 0.0, "y behind the exit ray");
                    assert!(
                        dot3(miss, miss).sqrt() < 1e-4,
                        "{kind:?} misses y by {miss:?}: {p:?}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 500, "only {checked} paths found");
    }

    /// dω/dA⊥ against the area a small cone of directions about each
    /// path's first direction covers across its exit ray at `y`, traced in
    /// 3D.
    #[test]
    fn the_spread_is_the_solid_angle_per_area_across_the_exit_ray() {
        let mut rng = SplitMix(11);
        let mut checked = 0;
        while checked < 300 {
            let x = random_point(&mut rng, -1.5, 1.5);
            let y = random_point(&mut rng, -1.5, 1.5);
            for kind in Kind::SEARCHED {
                for p in BALL.paths(kind, x, y).iter().filter(|p| p.cos_in > 0.5) {
                    let d = to64(p.dir);
                    let (a, b) = across(p.dir);
                    let h = 1e-5;
                    let land = |e: D3, s: f64| {
                        let (exit, out) = through(&BALL, kind, to64(x), unit(add3(d, e, s)))?;
                        Some(on_plane(exit, out, to64(y), to64(p.out)))
                    };
                    let (Some(a0), Some(a1), Some(b0), Some(b1)) =
                        (land(a, -h), land(a, h), land(b, -h), land(b, h))
                    else {
                        continue;
                    };
                    let (da, db) = (sub3(a1, a0), sub3(b1, b0));
                    let cross = [
                        da[1] * db[2] - da[2] * db[1],
                        da[2] * db[0] - da[0] * db[2],
                        da[0] * db[1] - da[1] * db[0],
                    ];
                    let area_per_sr = dot3(cross, cross).sqrt() / (4.0 * h * h);
                    let want = 1.0 / area_per_sr;
                    let got = p.spread as f64;
                    // Near the caustic the map folds and differences fail.
                    if !(want.is_finite() && want < 1e4) {
                        continue;
                    }
                    assert!(
                        (got - want).abs() <= 2e-3 * want,
                        "{kind:?}: spread {got} against {want} (x {x:?}, y {y:?})"
                    );
                    checked += 1;
                }
            }
        }
    }

    /// The grid traced lane by lane for both kinds through the ball
    /// (`sweep.rs`) is g as the plane traces it, to rounding.
    #[test]
    fn the_sweep_is_the_planes_trace() {
        let mut rng = SplitMix(4);
        for _ in 0..500 {
            let x = random_point(&mut rng, 0.26, 3.0);
            let y = random_point(&mut rng, 0.26, 3.0);
            let Some(search) = BALL.search(x, y) else {
                continue;
            };
            let (r, eta) = (BALL.radius as f64, BALL.eta as f64);
            let setting = Setting {
                dx: search.dx,
                y: (search.along, search.rho),
                r,
                eta,
            };
            let swept = setting.sweep();
            for k in 0..THROUGH {
                let kind = Kind::Through(k as u8);
                let plane = search.plane(kind);
                for (i, &(s, c)) in GRID.iter().enumerate() {
                    let (g, ahead) = plane.miss(s, c);
                    let got = swept.g[k][i];
                    assert!(
                        (got - g).abs() <= 1e-12 * plane.scale,
                        "{kind:?} {s}: {got} {g}"
                    );
                    if g.abs() > 1e-9 * plane.scale {
                        assert_eq!(swept.ahead[k][i], ahead, "{kind:?} {s}");
                    }
                }
            }
        }
    }

    /// Rays from `x` through the ball onto the floor: the search finds
    /// each one's path from where it lands, even where two paths merge
    /// at the caustic's edge.
    #[test]
    fn the_search_finds_the_paths_rays_through_the_ball_take() {
        for kind in Kind::SEARCHED {
            let mut rng = SplitMix(3);
            let x = to64(Vec3::new(0.6, 0.05, 0.3));
            let c = to64(BALL.center);
            let axis = unit(sub3(c, x));
            let (mut landed, mut found) = (0, 0);
            while landed < 40000 {
                let u = [0.0; 3].map(|_: f64| rng.next_f32() as f64 - 0.5);
                let d = unit(add3(axis, u, 1.0));
                let Some((exit, out)) = through(&BALL, kind, x, d) else {
                    continue;
                };
                // Onto the floor or a ceiling 2 m up.
                let h = if out[1] < 0.0 { 0.0 } else { 2.0 };
                if out[1].abs() < 1e-3 {
                    continue;
                }
                let y = on_plane(exit, out, [0.0, h, 0.0], [0.0, 1.0, 0.0]);
                let y = Vec3::new(y[0] as f32, h as f32, y[2] as f32);
                landed += 1;
                let dir = Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32);
                let x = Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32);
                let same = |p: &Refracted| p.dir.cross(dir).length() < 2e-4;
                if BALL.paths(kind, x, y).iter().any(same) {
                    found += 1;
                }
            }
            // Every one, but with reflections inside, where two roots can
            // lie closer than f32 directions tell (the rainbows' folds):
            // 2 in 40 000 with one reflection, 4 with two, 16 with three
            // (without the fold search 1 % of them were missed, and 5 %
            // with a reflection inside; 10 % with two).
            let least = match kind {
                Kind::Through(1 | 2) => 0.9995,
                Kind::Through(3) => 0.999,
                _ => 1.0,
            };
            assert!(
                found as f64 >= least * landed as f64,
                "{kind:?}: {found} of {landed}"
            );
        }
    }

    /// A path traced from its first direction (as a light subpath traces
    /// it, the other way) is found again by `path_along` from that
    /// direction alone: the path the full search finds, with the same
    /// Jacobian, for every kind.
    #[test]
    fn the_path_along_a_traced_direction_is_the_one_searched() {
        for kind in Kind::SEARCHED {
            let mut rng = SplitMix(5);
            let x = to64(Vec3::new(-0.4, 0.02, 0.5));
            let axis = unit(sub3(to64(BALL.center), x));
            let (mut landed, mut along, mut same, mut close) = (0, 0, 0, 0);
            while landed < 4000 {
                let u = [0.0; 3].map(|_: f64| rng.next_f32() as f64 - 0.5);
                let d = unit(add3(axis, u, 0.8));
                let Some((exit, out)) = through(&BALL, kind, x, d) else {
                    continue;
                };
                if out[1] < 1e-3 {
                    continue;
                }
                let y = on_plane(exit, out, [0.0, 1.6, 0.0], [0.0, 1.0, 0.0]);
                let y = Vec3::new(y[0] as f32, 1.6, y[2] as f32);
                let dir = Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32);
                let xf = Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32);
                landed += 1;
                let Some(search) = BALL.search(xf, y) else {
                    continue;
                };
                let Some(p) = search.path_along(kind, dir) else {
                    continue;
                };
                assert!(
                    p.dir.cross(dir).length() < 1e-3,
                    "{kind:?}: {p:?} for {dir:?}"
                );
                along += 1;
                // The same root: near a fold two lie close together.
                let near = |q: &&Refracted| q.dir.cross(p.dir).length() < 1e-6;
                if let Some(q) = search.paths(kind).iter().find(near) {
                    // Each slope by its own forward difference: by a fold,
                    // where g′ vanishes, they differ a little more.
                    let rel = (p.spread / q.spread - 1.0).abs();
                    assert!(
                        rel < 0.05,
                        "{kind:?}: spread {} against {}",
                        p.spread,
                        q.spread
                    );
                    same += 1;
                    close += (rel < 1e-3) as usize;
                }
            }
            // Found again but near grazing, where f32 directions blur the
            // root; and the search found the same path (but where it
            // misses one at a fold: `the_search_finds_…`).
            assert!(
                along as f64 >= 0.999 * landed as f64,
                "{kind:?}: {along} of {landed}"
            );
            assert!(
                same as f64 >= 0.998 * along as f64,
                "{kind:?}: {same} of {along}"
            );
            // Within 0.1 % but by folds (11 of 3 998 with one reflection
            // inside).
            assert!(
                close as f64 >= 0.99 * same as f64,
                "{kind:?}: {close} of {same}"
            );
        }
    }

    /// The solid angle a small lamp fills seen from floor points by way
    /// of the ball, two ways: over the lamp's area, Σ dω/dA_y over the
    /// paths found to each point (the estimator's Jacobian, and every
    /// root in the caustic, where there are three); and over directions
    /// in the ball's cone from x, the share whose 3D trace lands on the
    /// lamp. They agree within 4 standard errors.
    #[test]
    fn the_paths_found_fill_the_solid_angle_rays_find() {
        let ball = Ball::new(BALL.center, BALL.radius, 1.5);
        // A square lamp 16 cm wide, 1.6 m up, facing down.
        let (lc, half) = ([-0.3f64, 1.6, -0.3], 0.08f64);
        // Through: in the caustic (three paths) and about it; reflected:
        // around the ball, where its image of the lamp is seen; with two
        // and three reflections inside, light that carries little but
        // whose weights against BSDF sampling keep the fireflies away.
        let caustic = [(0.06, 0.06), (0.1, 0.12), (0.2, 0.1), (0.0, 0.3)];
        let around = [(0.5, 0.3), (-0.6, 0.2), (0.3, -0.5), (0.0, 0.6)];
        let mut rng = SplitMix(5);
        let kinds = [
            (Kind::Through(0), caustic),
            (Kind::Reflected, around),
            (Kind::Through(2), caustic),
            (Kind::Through(3), around),
        ];
        for (kind, floor) in kinds {
            for (fx, fz) in floor {
                let x = Vec3::new(fx, 0.0, fz);
                // Over the lamp's area.
                let n = 100_000;
                let (mut sum, mut sum2) = (0.0, 0.0);
                for _ in 0..n {
                    let mut at = |c: f64| (c + half * (2.0 * rng.next_f32() as f64 - 1.0)) as f32;
                    let y = Vec3::new(at(lc[0]), 1.6, at(lc[2]));
                    let v: f64 = ball
                        .paths(kind, x, y)
                        .iter()
                        .map(|p| (p.spread * p.out.y.abs()) as f64)
                        .sum();
                    sum += v;
                    sum2 += v * v;
                }
                let area = 4.0 * half * half;
                let mean = sum / n as f64;
                let by_area = mean * area;
                let se_area = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt() * area;
                // Over directions in the ball's cone.
                let x64 = to64(x);
                let to_c = sub3(to64(ball.center), x64);
                let dist = dot3(to_c, to_c).sqrt();
                let axis = scale3(to_c, 1.0 / dist);
                let cos_max = (1.0 - (ball.radius as f64 / dist).powi(2)).sqrt();
                let (u, v) = across(Vec3::new(axis[0] as f32, axis[1] as f32, axis[2] as f32));
                let m = 1_000_000;
                let mut hits = 0;
                for _ in 0..m {
                    let cz = 1.0 - rng.next_f32() as f64 * (1.0 - cos_max);
                    let sz = (1.0 - cz * cz).max(0.0).sqrt();
                    let phi = std::f64::consts::TAU * rng.next_f32() as f64;
                    let d = [0, 1, 2]
                        .map(|i| axis[i] * cz + sz * (phi.cos() * u[i] + phi.sin() * v[i]));
                    let Some((e, o)) = through(&ball, kind, x64, unit(d)) else {
                        continue;
                    };
                    let h = on_plane(e, o, lc, [0.0, 1.0, 0.0]);
                    if o[1] > 0.0 && (h[0] - lc[0]).abs() < half && (h[2] - lc[2]).abs() < half {
                        hits += 1;
                    }
                }
                let cone = std::f64::consts::TAU * (1.0 - cos_max);
                let share = hits as f64 / m as f64;
                let by_dir = share * cone;
                let se_dir = (share * (1.0 - share) / m as f64).sqrt() * cone;
                let tol = 4.0 * (se_area * se_area + se_dir * se_dir).sqrt();
                assert!(
                    hits > 100 && (by_area - by_dir).abs() <= tol,
                    "{kind:?} at {x:?}: {by_area} ± {se_area} by area, {by_dir} ± {se_dir} by direction"
                );
            }
        }
    }
}
