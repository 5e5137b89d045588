//! Where files named in a scene are looked for: Mitsuba 3's file resolver.
//!
//! Mitsuba resolves a relative file name against a list of folders, first
//! match wins: the folders of `<path value="…"/>` elements (the last one
//! declared first), then the scene file's folder, then the working
//! directory. Plugins resolve their files after the whole scene is parsed,
//! so a file named inside an `<include>`d fragment is found relative to the
//! *scene*, not to the fragment (Mitsuba 3's `src/core/parser.cpp` and
//! `fresolver.cpp`). scotopia adds one fallback after Mitsuba's list: the
//! folder of the file the element is written in, so fragments that name
//! files beside themselves load too.

use std::cell::RefCell;
use std::path::{Path, PathBuf};

thread_local! {
    /// The files resolved while [`recording`] runs on this thread (loading
    /// runs on one thread): what a checkpoint's fingerprint hashes.
    static RESOLVED: RefCell<Option<Vec<PathBuf>>> = const { RefCell::new(None) };
}

/// Runs `f` and returns with its result every file it resolved, in the
/// order first resolved, each once.
pub(crate) fn recording<T>(f: impl FnOnce() -> T) -> (T, Vec<PathBuf>) {
    let outer = RESOLVED.with(|r| r.replace(Some(Vec::new())));
    let out = f();
    let files = RESOLVED.with(|r| r.replace(outer)).unwrap_or_default();
    let mut seen = std::collections::HashSet::new();
    let files = files
        .into_iter()
        .filter(|f| seen.insert(f.clone()))
        .collect();
    (out, files)
}

fn note(path: &Path) {
    RESOLVED.with(|r| {
        if let Some(files) = r.borrow_mut().as_mut() {
            files.push(path.to_path_buf());
        }
    });
}

/// An ordered list of folders to look for files in.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SearchPath {
    folders: Vec<PathBuf>,
}

impl SearchPath {
    pub fn new(folders: Vec<PathBuf>) -> Self {
        Self { folders }
    }

    /// Just one folder.
    pub fn single(folder: &Path) -> Self {
        Self::new(vec![folder.to_path_buf()])
    }

    pub fn folders(&self) -> &[PathBuf] {
        &self.folders
    }

    /// The first folder holding `file`; if none does, `file` under the
    /// first folder (so an error names the path Mitsuba would read first).
    pub fn resolve(&self, file: &str) -> PathBuf {
        let found = self.find(file);
        note(&found);
        found
    }

    fn find(&self, file: &str) -> PathBuf {
        let p = Path::new(file);
        if p.is_absolute() {
            return p.to_path_buf();
        }
        self.folders
            .iter()
            .map(|f| f.join(p))
            .find(|c| c.exists())
            .unwrap_or_else(|| match self.folders.first() {
                Some(f) => f.join(p),
                None => p.to_path_buf(),
            })
    }
}

/// `file` looked up in `search` (see [`SearchPath::resolve`]).
pub fn resolve(search: &SearchPath, file: &str) -> PathBuf {
    search.resolve(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_folder_holding_the_file_wins() {
        let root = std::env::temp_dir().join(format!("scotopia-search-{}", std::process::id()));
        let (a, b) = (root.join("a"), root.join("b"));
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&b).unwrap();
        std::fs::write(b.join("m.ply"), "x").unwrap();
        let s = SearchPath::new(vec![a.clone(), b.clone()]);
        assert_eq!(s.resolve("m.ply"), b.join("m.ply"));
        assert_eq!(
            s.resolve("none.ply"),
            a.join("none.ply"),
            "missing: first folder"
        );
        std::fs::write(a.join("m.ply"), "x").unwrap();
        assert_eq!(s.resolve("m.ply"), a.join("m.ply"));
        let abs = b.join("m.ply");
        assert_eq!(s.resolve(abs.to_str().unwrap()), abs);
    }
}
