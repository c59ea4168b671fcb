//! ARCHITECTURE.md's layering as a test: no two modules of the library import each other.
//!
//! Every `super::…` and `crate::…` path in the library's non-test code is resolved to the
//! module it names, through the `pub use` re-exports of `mod.rs` and `lib.rs` (so
//! `super::orient2d` in the kernel is the `orient` file); a pair of modules that use each
//! other, neither inside the other, is a cycle. Doc comments and test modules are left out:
//! tests may reach upward.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Module path (`exact/boolean`, `` for the crate root) → the file's text, non-test code only.
fn sources() -> BTreeMap<String, (String, bool)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    let mut dirs = vec![root.clone()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).expect("src is readable") {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    let mut out = BTreeMap::new();
    for path in files {
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default();
        // Test-only files: `tests.rs`, the kernel's rational oracle, shared test meshes.
        if name == "tests" || name == "oracle" || name.starts_with("test_") {
            continue;
        }
        let is_mod = name == "mod" || name == "lib";
        let text = std::fs::read_to_string(&path).expect("a source file is readable");
        let code = text
            .split("#[cfg(test)]\nmod tests")
            .next()
            .unwrap_or_default();
        let code: String = (code.lines())
            .filter(|l| !l.trim_start().starts_with("//"))
            .map(|l| format!("{l}\n"))
            .collect();
        out.insert(module_of(&root, &path, is_mod), (code, is_mod));
    }
    out
}

fn module_of(root: &Path, path: &Path, is_mod: bool) -> String {
    let rel: PathBuf = path
        .strip_prefix(root)
        .expect("below src")
        .with_extension("");
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    if is_mod {
        parts.pop();
    }
    parts.join("/")
}

/// The paths after every `super::` or `crate::` in `code`: the segments, with a `{…}` group
/// at the end expanded into one path per item (its first segment).
fn paths(code: &str) -> Vec<(bool, Vec<String>)> {
    let mut out = Vec::new();
    for (start, keyword) in ["super::", "crate::"]
        .iter()
        .flat_map(|k| code.match_indices(k).map(move |(i, _)| (i, *k)))
    {
        let before = code[..start].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &code[start + keyword.len()..];
        let mut segments = Vec::new();
        let mut tail = rest;
        loop {
            let ident: String = (tail.chars())
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if ident.is_empty() {
                break;
            }
            tail = &tail[ident.len()..];
            segments.push(ident);
            match tail.strip_prefix("::") {
                Some(next) => tail = next,
                None => break,
            }
        }
        let super_ = keyword == "super::";
        match tail.strip_prefix('{') {
            Some(group) => {
                let group = group.split('}').next().unwrap_or_default();
                for item in group.split(',') {
                    let first = item.trim().split("::").next().unwrap_or_default();
                    if !first.is_empty() {
                        let mut path = segments.clone();
                        path.push(first.to_owned());
                        out.push((super_, path));
                    }
                }
            }
            None => out.push((super_, segments)),
        }
    }
    out
}

#[test]
fn no_two_modules_import_each_other() {
    let sources = sources();
    // Re-exports: module → item → the submodule that defines it.
    let mut reexports: BTreeMap<&str, BTreeMap<String, String>> = BTreeMap::new();
    for (module, (code, is_mod)) in &sources {
        if !is_mod {
            continue;
        }
        for line in code.split(';') {
            let line = line.trim();
            let Some(rest) =
                (line.strip_prefix("pub use ")).or_else(|| line.strip_prefix("pub(crate) use "))
            else {
                continue;
            };
            let (sub, items) = rest.split_once("::").unwrap_or((rest, ""));
            let sub = if module.is_empty() {
                sub.to_owned()
            } else {
                format!("{module}/{sub}")
            };
            for item in items.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
                if !item.is_empty() {
                    reexports
                        .entry(module)
                        .or_default()
                        .insert(item.to_owned(), sub.clone());
                }
            }
        }
    }
    let resolve = |path: &[String]| -> String {
        for len in (0..=path.len()).rev() {
            let module = path[..len].join("/");
            if sources.contains_key(&module) {
                if let Some(sub) = path
                    .get(len)
                    .and_then(|item| reexports.get(module.as_str())?.get(item))
                {
                    return sub.clone();
                }
                return module;
            }
        }
        String::new()
    };
    let inside = |a: &str, b: &str| a == b || b.is_empty() || a.starts_with(&format!("{b}/"));
    let mut uses: BTreeMap<&str, BTreeSet<String>> = BTreeMap::new();
    for (module, (code, _)) in &sources {
        let here: Vec<String> = module
            .split('/')
            .filter(|s| !s.is_empty())
            .map(str::to_owned)
            .collect();
        let parent = &here[..here.len().saturating_sub(1)];
        for (is_super, path) in paths(code) {
            let full: Vec<String> = if is_super {
                parent.iter().cloned().chain(path).collect()
            } else {
                path
            };
            let target = resolve(&full);
            if !inside(module, &target) {
                uses.entry(module).or_default().insert(target);
            }
        }
    }
    let mut cycles = Vec::new();
    for (&a, targets) in &uses {
        for b in targets {
            let back = uses
                .get(b.as_str())
                .is_some_and(|t| t.iter().any(|x| inside(a, x)));
            if back && a < b.as_str() && !inside(b, a) {
                cycles.push(format!("{a} ⇄ {b}"));
            }
        }
    }
    assert!(
        uses.len() > 50,
        "the scan found the modules: {:?}",
        uses.keys()
    );
    assert!(
        cycles.is_empty(),
        "modules that import each other: {cycles:?}"
    );
}
