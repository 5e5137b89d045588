use super::*;
use crate::test_rng::{chi2_z, Rng};

/// A lobe around `axis` (exp(κ(cos − 1))) over a constant floor: the
/// radiance a guide learns in the tests.
fn radiance(d: Vec3, axis: Vec3, kappa: f32) -> f32 {
    0.05 + (kappa * (d.dot(axis) - 1.0)).exp()
}

fn uniform_direction(rng: &mut Rng) -> Vec3 {
    from_square([rng.next(), rng.next()])
}

/// A quadtree learned over `iterations` from `n` uniform records each.
fn learned_tree(axis: Vec3, kappa: f32, iterations: usize, n: usize, seed: u64) -> DTree {
    let mut rng = Rng(seed);
    let mut building = DTree::default();
    let mut sampling = DTree::default();
    for _ in 0..iterations {
        let mut stats = vec![0.0f64; building.slots()];
        let mut square = vec![0.0f64; building.slots()];
        let mut lit = vec![0u64; building.slots()];
        for _ in 0..n {
            let d = uniform_direction(&mut rng);
            // L over the uniform density 1/4π.
            let slot = building.slot(d) as usize;
            let e = f64::from(radiance(d, axis, kappa)) * 4.0 * std::f64::consts::PI;
            stats[slot] += e;
            square[slot] += e * e;
            lit[slot] += 1;
        }
        sampling = building.with_energy(&stats, &square, &lit);
        building = sampling.refined();
    }
    sampling
}

#[test]
fn the_map_is_a_bijection_of_the_sphere() {
    let mut rng = Rng(1);
    for _ in 0..1000 {
        let s = [rng.next(), rng.next()];
        let d = from_square(s);
        assert!((d.length() - 1.0).abs() < 1e-5);
        let t = to_square(d);
        assert!((t[0] - s[0]).abs() < 1e-4, "{s:?} → {t:?}");
        let dv = (t[1] - s[1]).abs();
        assert!(dv < 1e-4 || (1.0 - dv) < 1e-4, "{s:?} → {t:?}");
    }
}

#[test]
fn learning_refines_where_the_light_is() {
    let axis = Vec3::new(0.3, -0.5, 0.81).normalize();
    let t = learned_tree(axis, 40.0, 6, 100_000, 3);
    assert!(t.leaves() > 40, "{} leaves", t.leaves());
    // The lobe (21× the radiance of the opposite side at its peak) is
    // far denser there, though averaged over its leaves.
    assert!(
        t.pdf(axis) > 10.0 * t.pdf(-axis),
        "{} vs {}",
        t.pdf(axis),
        t.pdf(-axis)
    );
}

#[test]
fn the_density_integrates_to_one() {
    let axis = Vec3::new(-0.2, 0.9, 0.1).normalize();
    let t = learned_tree(axis, 60.0, 6, 50_000, 5);
    let p: f64 = t.leaf_squares().iter().map(|l| l.2).sum();
    assert!((p - 1.0).abs() < 1e-5, "leaf probabilities sum to {p}");
    // The density in solid angle, integrated on a fine grid of the square
    // (Jacobian 4π), is one too.
    let n = 512;
    let mut sum = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            let s = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
            sum += f64::from(t.pdf(from_square(s)));
        }
    }
    let integral = sum * 4.0 * std::f64::consts::PI / (n * n) as f64;
    assert!((integral - 1.0).abs() < 0.01, "∫pdf dω = {integral}");
}

#[test]
fn samples_come_with_their_density_and_its_frequencies() {
    for (axis, kappa, seed) in [
        (Vec3::new(0.0, 0.0, 1.0), 30.0, 7u64),
        (Vec3::new(0.6, 0.64, -0.48).normalize(), 200.0, 8),
        (Vec3::new(-1.0, 0.0, 0.0), 5.0, 9),
    ] {
        let t = learned_tree(axis, kappa, 6, 60_000, seed);
        // Bins: a 16 × 16 grid of the square, expected counts from the
        // leaves' probabilities by area of overlap (exact: the density is
        // constant on each leaf).
        let g = 16usize;
        let mut expected = vec![0.0f64; g * g];
        for (lo, size, p) in t.leaf_squares() {
            let (i0, i1) = (
                (lo[0] * g as f64) as usize,
                ((lo[0] + size) * g as f64).ceil() as usize,
            );
            let (j0, j1) = (
                (lo[1] * g as f64) as usize,
                ((lo[1] + size) * g as f64).ceil() as usize,
            );
            for i in i0..i1.min(g) {
                for j in j0..j1.min(g) {
                    let (a0, a1) = (i as f64 / g as f64, (i + 1) as f64 / g as f64);
                    let (b0, b1) = (j as f64 / g as f64, (j + 1) as f64 / g as f64);
                    let w = (a1.min(lo[0] + size) - a0.max(lo[0])).max(0.0)
                        * (b1.min(lo[1] + size) - b0.max(lo[1])).max(0.0);
                    expected[i + g * j] += p * w / (size * size);
                }
            }
        }
        let count = 200_000usize;
        let mut hits = vec![0u64; g * g];
        let mut rng = Rng(seed + 100);
        // A direction on a quadrant's edge may map back to its neighbour
        // (f32 rounding of the map): rare, and the integrators weigh by
        // `pdf(d)` on both strategies, so it costs nothing but a bit of
        // efficiency.
        let mut edges = 0;
        for _ in 0..count {
            let (d, pdf) = t.sample([rng.next(), rng.next()]).expect("energy");
            let p = t.pdf(d);
            edges += usize::from((pdf - p).abs() > 1e-3 * p.max(1e-3));
            let s = to_square(d);
            let (i, j) = (
                ((s[0] * g as f32) as usize).min(g - 1),
                ((s[1] * g as f32) as usize).min(g - 1),
            );
            hits[i + g * j] += 1;
        }
        assert!(
            edges * 2000 < count,
            "{edges} samples without their density"
        );
        let expected: Vec<f64> = expected.iter().map(|e| e * count as f64).collect();
        let (z, chi2, dof) = chi2_z(&expected, &hits).expect("bins");
        assert!(z < 3.0902, "κ = {kappa}: χ² = {chi2} over {dof} dof");
    }
}

/// One iteration's records: `n` vertices facing up at points uniform in
/// the box, directions uniform, lit by a sharp lobe around `axis`.
fn iterate(field: &Field, n: usize, axis: Vec3, rng: &mut Rng, spp: u32) -> Field {
    iterate_over(field, n, axis, rng, spp, 1.0)
}

/// [`iterate`] with the points in the box's first `share` along x.
fn iterate_over(field: &Field, n: usize, axis: Vec3, rng: &mut Rng, spp: u32, share: f32) -> Field {
    iterate_lit(field, n, (axis, 200.0), rng, spp, share)
}

/// [`iterate_over`] lit by exp(`sharp` (d · axis − 1)): uniform light
/// at `sharp` = 0.
fn iterate_lit(
    field: &Field,
    n: usize,
    light: (Vec3, f32),
    rng: &mut Rng,
    spp: u32,
    share: f32,
) -> Field {
    field.next(&records_lit(field, n, light, rng, share), spp)
}

/// The records of [`iterate_lit`], before they are learned.
fn records_lit(
    field: &Field,
    n: usize,
    (axis, sharp): (Vec3, f32),
    rng: &mut Rng,
    share: f32,
) -> Stats {
    let (lo, hi) = (Vec3::new(-10.0, 0.0, -1.0), Vec3::new(10.0, 2.0, 1.0));
    let up = side(Some(Vec3::new(0.0, 1.0, 0.0)));
    let mut stats = Stats::new(field);
    let records = (0..n)
        .map(|_| {
            let u = Vec3::new(share * rng.next(), rng.next(), rng.next());
            let p = lo + (hi - lo).mul_elem(u);
            let d = uniform_direction(rng);
            (field.at(p, up).slot(d), (sharp * (d.dot(axis) - 1.0)).exp())
        })
        .collect();
    stats.add(&RowStats::of(records));
    stats
}

/// A guide over the slab after `iterations` of `n` records each, lit
/// by exp(`sharp` (d · y − 1)) over the box's first `share` along x.
fn guide_lit(iterations: usize, n: usize, sharp: f32, share: f32) -> Guide {
    let Slab { lo, hi, axis, .. } = slab();
    let mut guide = Guide::new(lo, hi);
    let mut rng = Rng(17);
    for _ in 0..iterations {
        let stats = records_lit(guide.field(), n, (axis, sharp), &mut rng, share);
        guide.advance(&stats);
    }
    guide
}

/// Σ n_k·w_k over the learning iterations.
fn spent(guide: &Guide) -> f32 {
    (0..BOUNDARIES.len() - 1)
        .map(|k| guide.weight(k) * (BOUNDARIES[k + 1] - BOUNDARIES[k]) as f32)
        .sum()
}

#[test]
fn a_field_is_worth_the_share_of_the_bounces_its_guiding_cells_would_improve() {
    // Sharp light everywhere: every cell guides, and is predicted to
    // remove most of its bounces' variance.
    let sharp = guide_lit(3, 100_000, 200.0, 1.0);
    let w = sharp.field().worth();
    assert!(w > 0.5 && w <= 1.0, "{w}");
    // Paths that bounce all over the slab, but find light only on its
    // first tenth along x: about a tenth as much.
    let Slab { lo, hi, up, axis } = slab();
    let mut field = Field::new(lo, hi);
    let mut rng = Rng(23);
    for spp in [1, 1, 2] {
        let mut stats = Stats::new(&field);
        let records = (0..200_000)
            .map(|_| {
                let u = Vec3::new(rng.next(), rng.next(), rng.next());
                let p = lo + (hi - lo).mul_elem(u);
                let d = uniform_direction(&mut rng);
                let e = if u.x < 0.1 {
                    (200.0 * (d.dot(axis) - 1.0)).exp()
                } else {
                    0.0
                };
                (field.at(p, up).slot(d), e)
            })
            .collect();
        stats.add(&RowStats::of(records));
        field = field.next(&stats, spp);
    }
    let part = field.worth();
    assert!(
        part > 0.7 * w * 0.1 && part < 1.3 * w * 0.1,
        "{part} against {w}"
    );
    // Uniform light: nothing to gain anywhere.
    assert_eq!(guide_lit(3, 100_000, 0.0, 1.0).field().worth(), 0.0);
    // Light found by a handful of records (fewer than MIN_LIT) is too
    // rare to predict from, and may be what guiding is for: worth all.
    let mut rare = Guide::new(lo, hi);
    for _ in 0..2 {
        let mut stats = Stats::new(rare.field());
        let records = (0..2000)
            .map(|i| {
                let p = lo + (hi - lo).mul_elem(Vec3::new(rng.next(), rng.next(), rng.next()));
                (
                    rare.field().at(p, up).slot(axis),
                    if i % 200 == 0 { 1.0 } else { 0.0 },
                )
            })
            .collect();
        stats.add(&RowStats::of(records));
        rare.advance(&stats);
    }
    assert_eq!(rare.field().worth(), 1.0);
    assert!(!rare.stopped());
}

#[test]
fn a_guide_worth_too_little_stops_and_its_learning_samples_keep_their_budget() {
    // Uniform light predicts no gain: after DOUBTS iterations the guide
    // stops, and the learning samples still to come weigh 1 but the
    // last iteration's, which takes what is left of the budget.
    let flat = guide_lit(2, 100_000, 0.0, 1.0);
    assert!(flat.stopped());
    let last = (BUDGET - 1.0 / 16.0 - 1.0 / 8.0 - 2.0 - 4.0) / 8.0;
    let w: Vec<f32> = (0..6).map(|k| flat.weight(k)).collect();
    assert_eq!(w, [0.0625, 0.125, 1.0, 1.0, last, 1.0]);
    assert!((spent(&flat) - BUDGET).abs() < 1e-5);
    // It learns no more.
    let mut more = flat.clone();
    more.advance(&Stats::new(flat.field()));
    assert_eq!(more, flat);
    // Where guiding pays it goes on, each iteration weighing twice the
    // one before but the last, and the budget is the same.
    let mut sharp = guide_lit(2, 100_000, 200.0, 1.0);
    assert!(!sharp.stopped());
    assert_eq!(sharp.weight(2), 0.25);
    let mut rng = Rng(5);
    for _ in 2..5 {
        let stats = records_lit(sharp.field(), 100_000, (slab().axis, 200.0), &mut rng, 1.0);
        sharp.advance(&stats);
    }
    assert!(!sharp.stopped());
    let w: Vec<f32> = (0..6).map(|k| sharp.weight(k)).collect();
    let last = (BUDGET - 1.0 / 16.0 - 1.0 / 8.0 - 0.5 - 2.0) / 8.0;
    assert_eq!(w, [0.0625, 0.125, 0.25, 0.5, last, 1.0]);
    assert!((spent(&sharp) - BUDGET).abs() < 1e-5);
}

#[test]
fn a_guide_declined_by_its_probe_weighs_every_sample_as_one_and_learns_nothing() {
    let flat = guide_lit(2, 100_000, 0.0, 1.0);
    let declined = Guide::declined(flat.field().clone());
    assert!(declined.stopped());
    assert_eq!(declined.learned(), 0);
    assert_eq!(declined.field().worth(), flat.field().worth());
    let w: Vec<f32> = (0..8).map(|k| declined.weight(k)).collect();
    assert_eq!(w, [1.0; 8]);
    let mut more = declined.clone();
    more.advance(&Stats::new(declined.field()));
    assert_eq!(more, declined);
}

/// The tests' field: a slab 20 m × 2 m × 2 m, seen from above (`up`),
/// lit along `axis`.
struct Slab {
    lo: Vec3,
    hi: Vec3,
    up: usize,
    axis: Vec3,
}

fn slab() -> Slab {
    let axis = Vec3::new(0.0, 1.0, 0.0);
    Slab {
        lo: Vec3::new(-10.0, 0.0, -1.0),
        hi: Vec3::new(10.0, 2.0, 1.0),
        up: side(Some(axis)),
        axis,
    }
}

#[test]
fn a_cell_with_many_records_is_halved_and_keeps_its_light() {
    let Slab { lo, hi, up, axis } = slab();
    let mut rng = Rng(11);
    let first = iterate(&Field::new(lo, hi), 100_000, axis, &mut rng, 1);
    // 100 000 records over c = 12 000: halved 4 times, into 16 cells;
    // their densities are the root's four quadrants, too flat to guide.
    assert_eq!(first.size().0, 16);
    assert!(first.at(lo, up).guide().is_none());
    // Refined where the light is, they guide.
    let second = iterate(&first, 100_000, axis, &mut rng, 2);
    for p in [lo, hi, Vec3::new(3.0, 0.5, 0.2)] {
        let g = second
            .at(p, up)
            .guide()
            .expect("every cell learned the light");
        assert!(g.pdf(axis) > 10.0 * g.pdf(-axis));
        // The other sides learned nothing.
        assert!(second.at(p, side(None)).guide().is_none());
    }
    // Cells along the long side: x splits first.
    assert_ne!(
        first.at(Vec3::new(-9.0, 1.0, 0.0), up).cell,
        first.at(Vec3::new(9.0, 1.0, 0.0), up).cell
    );
}

#[test]
fn each_side_of_a_surface_and_media_have_their_own_density() {
    let sides: Vec<usize> = [
        Vec3::new(1.0, 0.2, 0.1),
        Vec3::new(-1.0, 0.2, 0.1),
        Vec3::new(0.3, 0.9, -0.2),
        Vec3::new(0.3, -0.9, -0.2),
        Vec3::new(0.0, 0.1, 0.7),
        Vec3::new(0.0, 0.1, -0.7),
    ]
    .into_iter()
    .map(|n| side(Some(n)))
    .collect();
    assert_eq!(sides, vec![0, 1, 2, 3, 4, 5]);
    assert_eq!(side(None), SIDES - 1);
}

#[test]
fn rows_sum_their_records_in_order() {
    let a = RowStats::of(vec![(3, 1.0), (1, 2.0), (3, 0.5), (0, 0.25)]);
    let b = RowStats::of(vec![(3, 1.0), (1, 0.0), (3, 0.5), (0, 0.25)]);
    // Slot, Σe, Σe², records, records that found light.
    assert_eq!(
        a.0,
        vec![
            (0, 0.25, 0.0625, 1, 1),
            (1, 2.0, 4.0, 1, 1),
            (3, 1.5, 1.25, 2, 2)
        ]
    );
    assert_eq!(b.0[1], (1, 0.0, 0.0, 1, 0));
}

#[test]
fn the_schedule_ends_iterations_at_its_boundaries() {
    // Five iterations, then the guide learns no more.
    let mut guide = Guide::new(slab().lo, slab().hi);
    let mut rng = Rng(9);
    for k in 0..7 {
        assert_eq!(guide.learned(), k.min(5));
        let stats = records_lit(guide.field(), 20_000, (slab().axis, 200.0), &mut rng, 1.0);
        guide.advance(&stats);
    }
    assert_eq!(guide.learned(), 5);
    assert!(!guide.stopped());
    assert_eq!(next_boundary(0), Some(1));
    assert_eq!(next_boundary(5), Some(8));
    assert_eq!(next_boundary(16), None);
}

#[test]
fn guiding_is_predicted_to_pay_where_light_is_peaked_alone() {
    // Light alike from every direction, at a surface facing +z (side 4):
    // with L constant, the mixture ½·cos/π + ½/(4π) against cos/π alone
    // gives second moments in the ratio 16·∫₀¹ c²/(4c + 1) dc
    // = 16·(1/16 + ln 5/64) = 1.402: guiding would raise the variance.
    let flat = learned_tree(Vec3::new(0.0, 0.0, 1.0), 0.0, 4, 100_000, 5);
    let g = flat.gain(4).unwrap();
    assert!((g - 1.402).abs() < 0.03, "flat light: {g}");
    // A lobe 0.1 rad wide above the surface over the constant floor: the
    // lobe holds a tenth of the energy but about 80 % of the cosine
    // estimate's second moment, where the mixture's density is about 3×
    // cosine sampling's; roughly 0.8·0.35·1.3 + 0.2·1.4 ≈ 0.64 in all.
    let axis = Vec3::new(0.2, 0.1, 0.97).normalize();
    let peaked = learned_tree(axis, 100.0, 6, 100_000, 5);
    let g = peaked.gain(4).unwrap();
    assert!(g < 0.75, "peaked light: {g}");
    // Seen from a surface facing away from the lobe, the light is flat.
    let below = peaked.gain(5).unwrap();
    assert!(below > 1.3, "from below: {below}");
    // Media have no cosine: no prediction.
    assert!(peaked.gain(6).is_none());
}

#[test]
fn each_cell_box_holds_the_points_found_in_it_and_the_boxes_fill_the_field() {
    let (lo, hi) = (Vec3::new(-10.0, 0.0, -1.0), Vec3::new(10.0, 2.0, 1.0));
    let (tree, _) = SpatialTree::new(lo, hi).split(|c| if c == 0 { 3 } else { 0 });
    let (tree, _) = tree.split(|c| c % 3);
    let boxes = tree.boxes();
    assert_eq!(boxes.len(), tree.cells());
    let volume: f32 = boxes
        .iter()
        .map(|(l, h)| (h.x - l.x) * (h.y - l.y) * (h.z - l.z))
        .sum();
    assert!((volume - 80.0).abs() < 1e-3, "{volume}");
    let mut rng = Rng(5);
    for _ in 0..1000 {
        let p = lo + (hi - lo).mul_elem(Vec3::new(rng.next(), rng.next(), rng.next()));
        let (l, h) = boxes[tree.cell(p) as usize];
        assert!(p.max(l) == p && p.min(h) == p, "{p:?} outside {l:?}..{h:?}");
    }
}

#[test]
fn only_points_near_a_guiding_cell_look_it_up() {
    let Slab { lo, hi, up, axis } = slab();
    let mut rng = Rng(11);
    let first = iterate(&Field::new(lo, hi), 100_000, axis, &mut rng, 1);
    assert!(!first.guides() && !first.may_guide(lo, up));
    // Light learned only on the left half guides only there.
    let second = iterate_over(&first, 200_000, axis, &mut rng, 2, 0.5);
    assert!(second.guides());
    assert!(second.may_guide(Vec3::new(-9.0, 1.0, 0.0), up));
    assert!(!second.may_guide(Vec3::new(9.0, 1.0, 0.0), up));
    assert!(!second.may_guide(Vec3::new(-9.0, 1.0, 0.0), side(None)));
}

#[test]
fn cells_that_twice_predict_no_gain_stop_learning_and_keep_what_they_learned() {
    let Slab { lo, hi, up, axis } = slab();
    let mut rng = Rng(3);
    // Uniform light predicts no gain (1.40): one iteration is a doubt,
    // two in a row and the cells record no more.
    let first = iterate_lit(&Field::new(lo, hi), 100_000, (axis, 0.0), &mut rng, 1, 1.0);
    assert!(first.may_learn(lo, up) && first.may_learn(hi, up));
    let second = iterate_lit(&first, 100_000, (axis, 0.0), &mut rng, 2, 1.0);
    assert!(!second.may_learn(lo, up) && !second.may_learn(hi, up));
    assert!(!second.guides());
    // Records that reach them anyway (a jittered neighbour's) change
    // nothing, not even a sharp light's; the other sides still learn.
    let third = iterate_lit(&second, 100_000, (axis, 200.0), &mut rng, 4, 1.0);
    assert_eq!(third, second);
    assert!(third.may_learn(lo, side(None)));
}
