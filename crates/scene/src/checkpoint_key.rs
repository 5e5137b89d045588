//! The key a checkpoint is stamped with: a fingerprint of everything the
//! sample sequence depends on. The command line and Python compute it here,
//! so a render checkpointed by one resumes in the other.

use std::io::Read;
use std::path::{Path, PathBuf};

use scotopia_render::film::{fingerprint, Source};
use scotopia_render::integrator::{Guiding, RenderOptions};

use crate::mitsuba::Parameters;
use crate::LoadOptions;

/// A render's fingerprint and the files it hashed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CheckpointKey {
    pub key: u64,
    /// Every plain file the scene read, with the hash of its content.
    pub sources: Vec<Source>,
}

/// The content of every file the scene read (`files`, from
/// [`crate::load_scene_tracked`]: the scene file, includes, meshes,
/// textures, spectra, photometric files), its parameters (sorted, so their
/// order does not matter), the film size override and the options that
/// change samples — not `spp` or `time_limit`, which only say how many
/// there are (a resumed render may ask for more). Folders (`<path>`) and
/// anything else not a plain file are left out.
pub fn checkpoint_key(
    files: &[PathBuf],
    params: &Parameters,
    load: &LoadOptions,
    options: &RenderOptions,
) -> Result<CheckpointKey, String> {
    let mut sources = Vec::new();
    for file in files {
        if std::fs::metadata(file).is_ok_and(|m| m.is_file()) {
            let hash = hash_file(file).map_err(|e| {
                format!(
                    "{}: cannot read it to fingerprint the render: {e}",
                    file.display()
                )
            })?;
            sources.push(Source {
                path: file.display().to_string(),
                hash,
            });
        }
    }
    let mut sorted: Vec<_> = params.iter().collect();
    sorted.sort();
    let mut text = format!(
        "{sorted:?} {:?} {} {:?} {} {:?} {:?} {:?} {:?}",
        load.resolution,
        options.seed,
        options.strategy,
        options.cluster,
        options.bands,
        options.integrator,
        // As [S, T], the text keys had before the strategy had a type:
        // checkpoints saved then still resume.
        options.only_strategy.map(|s| s.pair()),
        options.quantity,
    );
    // Guiding changes the samples; off keeps the keys saved before it.
    if options.guiding == Guiding::On {
        text.push_str(" guiding");
    }
    // The contents in the order read, not the paths: a project moved
    // whole to another folder still resumes.
    let hashes: Vec<u8> = sources.iter().flat_map(|s| s.hash.to_le_bytes()).collect();
    Ok(CheckpointKey {
        key: fingerprint(&[&hashes, text.as_bytes()]),
        sources,
    })
}

impl CheckpointKey {
    /// Why a checkpoint saved with `saved` files and key `key` does not
    /// resume this render, where a file tells: the first file whose
    /// content changed, or that is read now and was not then, or the other
    /// way round. `None` when the key matches, or when nothing here
    /// explains the difference (the options, the parameters).
    pub fn refusal(&self, key: u64, saved: &[Source]) -> Option<String> {
        if key == self.key {
            return None;
        }
        let edit = "since the checkpoint was saved: restore it, or delete the checkpoint and \
                    render afresh";
        let now = |path: &str| self.sources.iter().find(|n| n.path == path);
        if let Some(s) = saved
            .iter()
            .find(|s| now(&s.path).is_some_and(|n| n.hash != s.hash))
        {
            return Some(format!("{} has changed {edit}", s.path));
        }
        // Names tell nothing when none is shared (a project moved whole).
        if !saved.iter().any(|s| now(&s.path).is_some()) {
            return None;
        }
        if let Some(s) = saved.iter().find(|s| now(&s.path).is_none()) {
            return Some(format!("the scene no longer reads {} {edit}", s.path));
        }
        self.sources
            .iter()
            .find(|n| !saved.iter().any(|s| s.path == n.path))
            .map(|n| format!("the scene reads {}, which it did not {edit}", n.path))
    }
}

/// XXH3-64 of the file's bytes, read in blocks (meshes may be large).
fn hash_file(path: &Path) -> std::io::Result<u64> {
    let mut file = scotopia_image::open_plain(path)?;
    let mut hash = xxhash_rust::xxh3::Xxh3::new();
    let mut buf = vec![0u8; 1 << 16];
    loop {
        let n = file.read(&mut buf)?;
        if n == 0 {
            return Ok(hash.digest());
        }
        hash.update(&buf[..n]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scotopia_render::integrator::ClusterSize;

    #[test]
    fn the_key_follows_what_changes_samples_and_nothing_else() {
        let dir = std::env::temp_dir().join(format!("scotopia-key-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("s.xml");
        let lamp = dir.join("lamp.ies");
        std::fs::write(&scene, "<scene version=\"3.0.0\"/>").unwrap();
        std::fs::write(&lamp, "IESNA:LM-63-2002").unwrap();
        let files = [scene.clone(), lamp.clone(), dir.clone()];
        let load = LoadOptions::default();
        let base = RenderOptions::default();
        let key = |p: &Parameters, o: &RenderOptions| checkpoint_key(&files, p, &load, o).unwrap();
        let mut a = Parameters::new();
        a.insert("x".into(), "1".into());
        a.insert("y".into(), "2".into());
        let k = key(&a, &base);
        // The folder is left out.
        assert_eq!(k.sources.len(), 2);
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
        // Another seed, cluster size or parameter value: another key,
        // which no file explains.
        let seed = RenderOptions {
            seed: 1,
            ..base.clone()
        };
        let cluster = RenderOptions {
            cluster: ClusterSize::K8,
            ..base.clone()
        };
        assert_ne!(key(&a, &seed).key, k.key);
        assert_eq!(key(&a, &seed).refusal(k.key, &k.sources), None);
        assert_ne!(key(&a, &cluster).key, k.key);
        let guided = RenderOptions {
            guiding: Guiding::On,
            ..base.clone()
        };
        assert_ne!(key(&a, &guided).key, k.key);
        b.insert("x".into(), "3".into());
        assert_ne!(key(&b, &base).key, k.key);
        // An edited file: another key, and the refusal names the file.
        std::fs::write(&lamp, "IESNA:LM-63-1995").unwrap();
        let edited = key(&a, &base);
        assert_ne!(edited.key, k.key);
        let why = edited.refusal(k.key, &k.sources).unwrap();
        assert!(why.contains("lamp.ies") && why.contains("changed"), "{why}");
        std::fs::write(&scene, "<scene version=\"3.0.0\"></scene>").unwrap();
        assert_ne!(key(&a, &base).key, edited.key);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
