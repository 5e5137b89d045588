//! Area emitters with a texture as `radiance` (Mitsuba 3's
//! `<emitter type="area"><texture name="radiance" …/></emitter>`): the
//! loader reads a nested bitmap, a referenced checkerboard and spectra in
//! it; seen directly, each texel lands where Mitsuba 3 puts it, with its
//! own radiance, whatever spectrum the wavelengths were drawn from; and
//! every bidirectional strategy that builds the light's paths (hitting it,
//! sampling it, starting light paths on it) finds the same image.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use scotopia_color::photometry::spectrum_to_xyzv;
use scotopia_color::{rgb_to_spectrum, RgbSpace, Spectrum, SpectrumKind, UpsampleMethod};
use scotopia_render::integrator::{render, BdptStrategy, RenderOptions};
use scotopia_render::light::Light;
use scotopia_render::scene::{IntegratorKind, Scene};
use scotopia_render::texture::Texture;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-area-tex-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The 2×2 bitmap: top row red | green, bottom row blue | white (linear).
const TEXELS: [[[f32; 3]; 2]; 2] = [
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, 1.0], [1.0, 1.0, 1.0]],
];

fn write_bitmap() {
    let data: Vec<f32> = TEXELS.iter().flatten().flatten().copied().collect();
    image::Rgb32FImage::from_raw(2, 2, data)
        .unwrap()
        .save(dir().join("quad.exr"))
        .unwrap();
}

fn load(name: &str, body: &str) -> Scene {
    let f = dir().join(format!("{name}.xml"));
    std::fs::write(&f, format!("<scene version=\"3.0.0\">\n{body}\n</scene>")).unwrap();
    load_scene(&f, &Parameters::new()).unwrap()
}

/// An orthographic view straight down −z onto the unit square [−1, 1]²,
/// `res`² pixels, box-filtered.
fn orthographic(res: u32) -> String {
    format!(
        r#"<sensor type="orthographic"><transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="{res}"/><integer name="height" value="{res}"/><rfilter type="box"/></film></sensor>"#
    )
}

fn image(scene: &Scene, options: RenderOptions) -> Vec<[f32; 4]> {
    render(scene, &options, &AtomicBool::new(false), &|_, _| {})
        .unwrap()
        .film
        .xyzv()
}

fn xyz(s: &Spectrum) -> [f64; 3] {
    let v = spectrum_to_xyzv(s);
    [v.x, v.y, v.z]
}

/// Mean over `pixels` of (rendered − expected) per X, Y, Z: zero within 4
/// standard errors (from the spread over the pixels, which are
/// independent), and that error small beside the level, so the check
/// means something.
fn unbiased(what: &str, pixels: &[([f32; 4], [f64; 3])]) {
    let n = pixels.len() as f64;
    for c in 0..3 {
        let d: Vec<f64> = pixels.iter().map(|(p, e)| p[c] as f64 - e[c]).collect();
        let mean = d.iter().sum::<f64>() / n;
        let se = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        let level = pixels.iter().map(|(_, e)| e[c]).sum::<f64>() / n;
        assert!(
            mean.abs() <= 4.0 * se && se < 0.05 * level,
            "{what}, channel {c}: difference {mean} ± {se} (level {level})"
        );
    }
}

#[test]
fn bitmap_texels_land_where_mitsuba_puts_them() {
    // A bitmap's v runs down its rows and a rectangle's v up its y, so a
    // view with +y up shows the image upside down, left to right as it
    // is: what Mitsuba 3.9 renders of this scene (scalar_rgb: top pixel
    // rows blue | white, bottom ones red | green).
    write_bitmap();
    let res = 4;
    let scene = load(
        "bitmap",
        &format!(
            r#"{}<shape type="rectangle"><emitter type="area">
  <texture type="bitmap" name="radiance"><string name="filename" value="quad.exr"/><string name="filter_type" value="nearest"/></texture>
</emitter></shape>"#,
            orthographic(res)
        ),
    );
    let Light::Area(a) = &scene.lights[0] else {
        panic!("{:?}", scene.lights)
    };
    assert!(matches!(a.radiance, Texture::Bitmap(_)));
    // A bitmap's RGB is upsampled unbounded, as Mitsuba stores it.
    let texel: Vec<Vec<[f64; 3]>> = TEXELS
        .iter()
        .map(|row| {
            row.iter()
                .map(|&rgb| {
                    xyz(&rgb_to_spectrum(
                        rgb,
                        RgbSpace::Srgb,
                        UpsampleMethod::Jakob2019,
                        SpectrumKind::Unbounded,
                    )
                    .unwrap())
                })
                .collect()
        })
        .collect();
    let rendered = image(
        &scene,
        RenderOptions {
            spp: Some(256),
            seed: 1,
            ..RenderOptions::default()
        },
    );
    let mut pixels = Vec::new();
    for (i, p) in rendered.iter().enumerate() {
        let (x, y) = (i % res as usize, i / res as usize);
        // Pixel column x shows texel column x/2; pixel row y texel row 1 − y/2.
        let want = texel[1 - y / 2][x / 2];
        // The nearest texel colour is the one expected there.
        let dist = |e: &[f64; 3]| (0..3).map(|c| (p[c] as f64 - e[c]).powi(2)).sum::<f64>();
        let nearest = texel
            .iter()
            .flatten()
            .min_by(|a, b| dist(a).total_cmp(&dist(b)))
            .unwrap();
        assert_eq!(nearest, &want, "pixel ({x}, {y}): {p:?}");
        pixels.push((*p, want));
    }
    unbiased("bitmap", &pixels);
}

#[test]
fn each_square_of_a_checkerboard_of_unlike_spectra_keeps_its_own_radiance() {
    // A bright blue line beside a dim red band: the light's mean spectrum,
    // which wavelengths are drawn from, is nearly all line, yet the red
    // squares converge to their own radiance (the estimate divides by the
    // density it drew with). The checkerboard is a top-level texture,
    // referenced.
    let res = 8;
    let scene = load(
        "checkerboard",
        &format!(
            r#"{}<texture type="checkerboard" id="squares">
  <spectrum name="color0" value="360:0, 440:0, 445:200, 450:0, 830:0"/>
  <spectrum name="color1" value="360:0, 560:0, 640:1, 830:1"/>
</texture>
<shape type="rectangle"><emitter type="area"><ref name="radiance" id="squares"/></emitter></shape>"#,
            orthographic(res)
        ),
    );
    let Light::Area(a) = &scene.lights[0] else {
        panic!("{:?}", scene.lights)
    };
    let Texture::Checkerboard(c) = &a.radiance else {
        panic!("{:?}", a.radiance)
    };
    let (Texture::Constant(line), Texture::Constant(band)) = (&c.color0, &c.color1) else {
        panic!("{c:?}")
    };
    assert_eq!((line.eval(445.0), band.eval(700.0)), (200.0, 1.0));
    let (xyz_line, xyz_band) = (xyz(line), xyz(band));
    // The mean the wavelengths come from: the line dominates it.
    let mean = a.mean_radiance();
    assert!(mean.eval(445.0) > 50.0 * mean.eval(700.0));
    let rendered = image(
        &scene,
        RenderOptions {
            spp: Some(64),
            seed: 2,
            ..RenderOptions::default()
        },
    );
    let (mut lines, mut bands) = (Vec::new(), Vec::new());
    for (i, p) in rendered.iter().enumerate() {
        // Pixel centres in uv: u to the right, v up (the view is down −z).
        let u = ((i % res as usize) as f64 + 0.5) / res as f64;
        let v = 1.0 - ((i / res as usize) as f64 + 0.5) / res as f64;
        if (u > 0.5) == (v > 0.5) {
            lines.push((*p, xyz_line));
        } else {
            bands.push((*p, xyz_band));
        }
    }
    unbiased("line squares", &lines);
    unbiased("band squares", &bands);
}

#[test]
fn every_strategy_finds_the_textured_light_alike() {
    // A diffuse floor under a bitmap rectangle and a checkerboard sphere,
    // both emitting, seen in perspective. Paths of two vertices (the
    // lights seen) are built by hitting the light (0, 2) and by starting
    // a light path on it (1, 1); paths of three (the floor lit) by
    // hitting it (0, 3), sampling it (1, 2) and starting on it (2, 1).
    // Each strategy alone, unweighted, must give the same image, region
    // by region (so a texture misplaced by one of them shows).
    write_bitmap();
    let res = 16usize;
    let body = format!(
        r#"<sensor type="perspective"><float name="fov" value="60"/>
  <transform name="to_world"><lookat origin="0,-3.5,2.5" target="0,0,0.4" up="0,0,1"/></transform>
  <film type="hdrfilm"><integer name="width" value="{res}"/><integer name="height" value="{res}"/><rfilter type="box"/></film></sensor>
<shape type="rectangle"><transform name="to_world"><scale value="2"/></transform><bsdf type="diffuse"/></shape>
<shape type="rectangle">
  <transform name="to_world"><scale x="0.8" y="0.6"/><rotate x="1" angle="150"/><translate z="1.2"/></transform>
  <emitter type="area"><texture type="bitmap" name="radiance"><string name="filename" value="quad.exr"/><string name="filter_type" value="nearest"/></texture></emitter>
</shape>
<shape type="sphere"><point name="center" value="1.1,0.4,0.5"/><float name="radius" value="0.35"/>
  <emitter type="area"><texture type="checkerboard" name="radiance"><rgb name="color0" value="0.2"/><rgb name="color1" value="3"/>
    <transform name="to_uv"><scale x="4" y="2"/></transform></texture></emitter>
</shape>"#
    );
    let scene = load("strategies", &body);
    // Per region of 4 × 4 pixels and per X, Y, Z: the region's sum in 16
    // independent renders, its mean and standard error over them.
    let regions = |s: usize, t: usize, spp: u32| -> Vec<[(f64, f64); 3]> {
        const RENDERS: usize = 16;
        let sums: Vec<Vec<[f64; 3]>> = (0..RENDERS)
            .map(|k| {
                let image = image(
                    &scene,
                    RenderOptions {
                        spp: Some(spp),
                        seed: (1000 * s + 100 * t + k) as u32,
                        integrator: Some(IntegratorKind::Bdpt),
                        only_strategy: Some(BdptStrategy::new(s, t).unwrap()),
                        ..RenderOptions::default()
                    },
                );
                let mut sums = vec![[0.0; 3]; 16];
                for (i, p) in image.iter().enumerate() {
                    let region = (i % res) * 4 / res + 4 * ((i / res) * 4 / res);
                    for c in 0..3 {
                        sums[region][c] += p[c] as f64;
                    }
                }
                sums
            })
            .collect();
        (0..16)
            .map(|r| {
                std::array::from_fn(|c| {
                    let x: Vec<f64> = sums.iter().map(|s| s[r][c]).collect();
                    let n = RENDERS as f64;
                    let mean = x.iter().sum::<f64>() / n;
                    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
                    (mean, (var / n).sqrt())
                })
            })
            .collect()
    };
    // 144 comparisons of means with 15-degree-of-freedom errors: 5 of them.
    let agree = |what: &str, a: &[[(f64, f64); 3]], b: &[[(f64, f64); 3]]| {
        for (r, (a, b)) in a.iter().zip(b).enumerate() {
            for c in 0..3 {
                let ((ma, sa), (mb, sb)) = (a[c], b[c]);
                let se = (sa * sa + sb * sb).sqrt();
                assert!(
                    (ma - mb).abs() <= 5.0 * se,
                    "{what}, region {r}, channel {c}: {ma} ± {sa} vs {mb} ± {sb}"
                );
            }
        }
    };
    let seen = regions(0, 2, 64);
    assert!(seen.iter().filter(|r| r[1].0 > 0.0).count() >= 4);
    agree("lights seen: hit vs light path", &seen, &regions(1, 1, 8));
    let lit = regions(1, 2, 8);
    assert!(lit.iter().filter(|r| r[1].0 > 0.0).count() >= 8);
    agree("floor lit: sampled vs hit", &lit, &regions(0, 3, 32));
    agree("floor lit: sampled vs light path", &lit, &regions(2, 1, 8));
}

#[test]
fn an_area_emitter_without_radiance_emits_mitsubas_default() {
    // Mitsuba's default radiance is 1 in its units: the normalised D65.
    let scene = load(
        "default",
        r#"<sensor type="perspective"/><shape type="sphere"><emitter type="area"/></shape>"#,
    );
    let Light::Area(a) = &scene.lights[0] else {
        panic!("{:?}", scene.lights)
    };
    let Texture::Constant(s) = &a.radiance else {
        panic!("{:?}", a.radiance)
    };
    let d65 = scotopia_scene::mitsuba::normalised_illuminant("d65").unwrap();
    assert_eq!(s.eval(500.0), d65.eval(500.0));
}
