//! Gaussian and Laplacian (band-pass) pyramids (Burt & Adelson 1983, "The
//! Laplacian Pyramid as a Compact Image Code"): each level is the one above
//! blurred by the 5-tap binomial kernel [1 4 6 4 1]/16 and halved; a band is
//! a level minus the next coarser level brought back up to its size. The
//! bands and the coarsest level sum back to the image exactly, whatever is
//! done to them in between — which is what the multiscale model needs.

use rayon::prelude::*;

/// One channel of an image, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    pub width: usize,
    pub height: usize,
    pub data: Vec<f32>,
}

impl Plane {
    pub fn new(width: usize, height: usize, data: Vec<f32>) -> Self {
        debug_assert_eq!(data.len(), width * height);
        Self {
            width,
            height,
            data,
        }
    }

    pub fn filled(width: usize, height: usize, value: f32) -> Self {
        Self::new(width, height, vec![value; width * height])
    }

    fn at(&self, x: usize, y: usize) -> f32 {
        self.data[y * self.width + x]
    }
}

/// The binomial kernel [1 4 6 4 1]/16.
const TAPS: [f32; 5] = [1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0];

/// Blurs with the binomial kernel (edges clamped) and keeps every second
/// sample: the next Gaussian level, of size ⌈w/2⌉ × ⌈h/2⌉.
pub fn reduce(p: &Plane) -> Plane {
    let (w, h) = (p.width, p.height);
    let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
    let clamp = |i: i64, n: usize| i.clamp(0, n as i64 - 1) as usize;
    // Horizontal pass on every row, keeping even columns.
    let mut rows = vec![0.0f32; nw * h];
    rows.par_chunks_mut(nw).enumerate().for_each(|(y, out)| {
        for (i, o) in out.iter_mut().enumerate() {
            let x = 2 * i as i64;
            *o = (0..5)
                .map(|k| TAPS[k] * p.at(clamp(x + k as i64 - 2, w), y))
                .sum();
        }
    });
    // Vertical pass, keeping even rows.
    let mut data = vec![0.0f32; nw * nh];
    data.par_chunks_mut(nw).enumerate().for_each(|(j, out)| {
        let y = 2 * j as i64;
        for (x, o) in out.iter_mut().enumerate() {
            *o = (0..5)
                .map(|k| TAPS[k] * rows[clamp(y + k as i64 - 2, h) * nw + x])
                .sum();
        }
    });
    Plane::new(nw, nh, data)
}

/// Brings a coarser level up to `width` × `height` by bilinear
/// interpolation (sample centres aligned: fine pixel x sits at coarse
/// coordinate (x + ½)/2 − ½).
pub fn expand(p: &Plane, width: usize, height: usize) -> Plane {
    let sx = p.width as f32 / width as f32;
    let sy = p.height as f32 / height as f32;
    let coord = |i: usize, s: f32, n: usize| {
        let c = ((i as f32 + 0.5) * s - 0.5).clamp(0.0, (n - 1) as f32);
        let i0 = c.floor() as usize;
        (i0, (i0 + 1).min(n - 1), c - i0 as f32)
    };
    let cols: Vec<(usize, usize, f32)> = (0..width).map(|x| coord(x, sx, p.width)).collect();
    let mut data = vec![0.0f32; width * height];
    data.par_chunks_mut(width).enumerate().for_each(|(y, out)| {
        let (y0, y1, fy) = coord(y, sy, p.height);
        for (o, &(x0, x1, fx)) in out.iter_mut().zip(&cols) {
            let top = p.at(x0, y0) + fx * (p.at(x1, y0) - p.at(x0, y0));
            let bottom = p.at(x0, y1) + fx * (p.at(x1, y1) - p.at(x0, y1));
            *o = top + fy * (bottom - top);
        }
    });
    Plane::new(width, height, data)
}

/// The Gaussian pyramid: `levels` planes, the image first, each next one
/// reduced, stopping early when a level would be smaller than 2 × 2.
pub fn gaussian(image: Plane, levels: usize) -> Vec<Plane> {
    let mut out = vec![image];
    while out.len() < levels.max(1) {
        let last = out.last().expect("the pyramid starts with the image");
        if last.width < 4 || last.height < 4 {
            break;
        }
        out.push(reduce(last));
    }
    out
}

/// For each Gaussian level but the last: the next coarser level expanded
/// to its size (the local mean around each pixel at that scale).
pub fn expanded_coarser(levels: &[Plane]) -> Vec<Plane> {
    levels
        .windows(2)
        .map(|pair| expand(&pair[1], pair[0].width, pair[0].height))
        .collect()
}

/// Sums band-pass planes (finest first) onto the coarsest level: the
/// inverse of taking bands `G_n − expand(G_{n+1})`.
pub fn collapse(bands: &[Plane], coarsest: Plane) -> Plane {
    collapse_with(bands, coarsest, |up, band| up + band)
}

/// Collapses with `combine(expanded coarser level, band)` in place of the
/// sum, for models that add a band as a contrast on the local mean.
pub fn collapse_with(
    bands: &[Plane],
    coarsest: Plane,
    combine: impl Fn(f32, f32) -> f32 + Sync,
) -> Plane {
    let mut acc = coarsest;
    for band in bands.iter().rev() {
        let mut up = expand(&acc, band.width, band.height);
        up.data
            .par_iter_mut()
            .zip(&band.data)
            .for_each(|(u, &b)| *u = combine(*u, b));
        acc = up;
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(w: usize, h: usize) -> Plane {
        let data = (0..w * h)
            .map(|i| ((i % w) as f32 * 0.7 + (i / w) as f32 * 1.3).sin() + 2.0)
            .collect();
        Plane::new(w, h, data)
    }

    #[test]
    fn reduce_halves_and_keeps_a_constant() {
        let p = reduce(&Plane::filled(9, 6, 3.5));
        assert_eq!((p.width, p.height), (5, 3));
        assert!(p.data.iter().all(|&v| (v - 3.5).abs() < 1e-6));
    }

    #[test]
    fn reduce_preserves_the_mean_of_a_smooth_image() {
        let img = ramp(64, 48);
        let mean = |p: &Plane| p.data.iter().sum::<f32>() / p.data.len() as f32;
        assert!((mean(&reduce(&img)) - mean(&img)).abs() < 0.02);
    }

    #[test]
    fn bands_and_the_coarsest_level_rebuild_the_image() {
        let img = ramp(37, 23);
        let g = gaussian(img.clone(), 5);
        assert_eq!(g.len(), 4, "stops before a level under 2×2");
        let up = expanded_coarser(&g);
        let bands: Vec<Plane> = g
            .iter()
            .zip(&up)
            .map(|(level, u)| {
                Plane::new(
                    level.width,
                    level.height,
                    level.data.iter().zip(&u.data).map(|(a, b)| a - b).collect(),
                )
            })
            .collect();
        let back = collapse(&bands, g.last().unwrap().clone());
        let err = back
            .data
            .iter()
            .zip(&img.data)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(err < 1e-5, "{err}");
    }
}
