//! The key a checkpoint is stamped with: a fingerprint of everything the
//! sample sequence depends on. The command line and Python compute it here,
//! so a render checkpointed by one resumes in the other.

use std::path::Path;

use scotopia_render::film::fingerprint;
use scotopia_render::integrator::RenderOptions;

use crate::mitsuba::Parameters;
use crate::LoadOptions;

/// The scene file's bytes, its parameters (sorted, so their order does not
/// matter), the film size override and the options that change samples —
/// not `spp` or `time_limit`, which only say how many there are (a resumed
/// render may ask for more). Included files are not read: a checkpoint is
/// for the same scene, edited files are the user's to keep unchanged.
pub fn checkpoint_key(
    scene: &Path,
    params: &Parameters,
    load: &LoadOptions,
    options: &RenderOptions,
) -> std::io::Result<u64> {
    let bytes = std::fs::read(scene)?;
    let mut sorted: Vec<_> = params.iter().collect();
    sorted.sort();
    let text = format!(
        "{sorted:?} {:?} {} {:?} {} {:?} {:?} {:?} {:?}",
        load.resolution,
        options.seed,
        options.strategy,
        options.cluster,
        options.bands,
        options.integrator,
        options.only_strategy,
        options.quantity,
    );
    Ok(fingerprint(&[&bytes, text.as_bytes()]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_key_follows_what_changes_samples_and_nothing_else() {
        let dir = std::env::temp_dir().join(format!("scotopia-key-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("s.xml");
        std::fs::write(&scene, "<scene version=\"3.0.0\"/>").unwrap();
        let load = LoadOptions::default();
        let base = RenderOptions::default();
        let key = |p: &Parameters, o: &RenderOptions| checkpoint_key(&scene, p, &load, o).unwrap();
        let mut a = Parameters::new();
        a.insert("x".into(), "1".into());
        a.insert("y".into(), "2".into());
        let k = key(&a, &base);
        // Same parameters, another insertion order; more samples or time.
        let mut b = Parameters::new();
        b.insert("y".into(), "2".into());
        b.insert("x".into(), "1".into());
        let more = RenderOptions {
            spp: Some(64),
            time_limit: Some(std::time::Duration::from_secs(5)),
            ..base.clone()
        };
        assert_eq!(key(&b, &more), k);
        // Another seed, cluster size or parameter value: another key.
        let seed = RenderOptions {
            seed: 1,
            ..base.clone()
        };
        let cluster = RenderOptions {
            cluster: 8,
            ..base.clone()
        };
        assert_ne!(key(&a, &seed), k);
        assert_ne!(key(&a, &cluster), k);
        b.insert("x".into(), "3".into());
        assert_ne!(key(&b, &base), k);
        std::fs::write(&scene, "<scene version=\"3.0.0\"></scene>").unwrap();
        assert_ne!(key(&a, &base), k);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
