//! Generates the Jakob & Hanika 2019 coefficient tables in data/rgb2spec/
//! with scotopia's own Gauss–Newton fitter (`make tables`).
//!
//! Usage: scotopia-rgb2spec [OUT_DIR] [SPACE…]   (default: data/rgb2spec, all spaces)

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use scotopia_color::upsample::jakob2019::{fit::Fitter, TABLE_RES};
use scotopia_color::RgbSpace;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().unwrap_or_else(|| "data/rgb2spec".into()));
    let names: Vec<String> = args.collect();
    let spaces: Vec<RgbSpace> = if names.is_empty() {
        RgbSpace::ALL.to_vec()
    } else {
        match names.iter().map(|n| RgbSpace::from_name(n)).collect() {
            Ok(s) => s,
            Err(e) => {
                eprintln!("scotopia-rgb2spec: {e}");
                return ExitCode::FAILURE;
            }
        }
    };
    for space in spaces {
        let start = Instant::now();
        let (table, worst) = Fitter::new(space).build_table(TABLE_RES);
        let bytes = table.encode();
        let path = out.join(format!("{}.sig", space.name()));
        let tmp = path.with_extension("sig.tmp");
        if let Err(e) = std::fs::write(&tmp, &bytes).and_then(|_| std::fs::rename(&tmp, &path)) {
            eprintln!("scotopia-rgb2spec: {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        println!(
            "{}: {}³×3 table, worst CIELAB residual {worst:.2e}, {} bytes, {:.1} s",
            space.name(),
            TABLE_RES,
            bytes.len(),
            start.elapsed().as_secs_f64()
        );
    }
    ExitCode::SUCCESS
}
