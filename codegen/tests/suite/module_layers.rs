//! The files of a module directory form a one-way chain of layers: no file uses, directly or
//! through others, a file that uses it back.
//!
//! A file uses another when it names it: `use super::x::…`, `use super::{x::…}`, a `super::x::`
//! path in its code, or the same through the crate (`crate::generate::emit::x::…`). The
//! directory's `mod.rs` is a file like the others: its `mod x;` declarations are not uses, but
//! a path through one of its children (`pub use x::Item;`, `x::f()`) is, and so is a child's
//! `super::Item` of an item `mod.rs` defines or re-exports. Inline modules (`mod tests { use
//! super::*; }`) refer to their own file. Comments and strings are not code, so they name
//! nothing.

use dyngen_testkit::workspace_root;
use proc_macro2::{Delimiter, Spacing, TokenStream, TokenTree};
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The directory's module, as the crate spells it: the file `x.rs` is `crate::<path>::x`.
struct ModuleDir<'a> {
    dir: &'a Path,
    crate_path: &'a [&'a str],
}

/// A path in a file, with the number of inline modules it is written in.
struct PathIn {
    depth: usize,
    segments: Vec<String>,
}

/// What each file of the directory uses of the others, by file stem (`mod` for `mod.rs`).
fn uses(module: &ModuleDir) -> BTreeMap<String, BTreeSet<String>> {
    let files: BTreeMap<String, String> = std::fs::read_dir(module.dir)
        .unwrap_or_else(|e| panic!("{}: {e}", module.dir.display()))
        .map(|entry| entry.expect("a directory entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "rs"))
        .map(|path| {
            let stem = path
                .file_stem()
                .expect("a file name")
                .to_string_lossy()
                .into_owned();
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            (stem, text)
        })
        .collect();
    let nodes: BTreeSet<String> = files.keys().cloned().collect();
    files
        .iter()
        .map(|(file, text)| {
            let tokens: TokenStream = text
                .parse()
                .unwrap_or_else(|e| panic!("{file}.rs does not tokenize: {e:?}"));
            let mut paths = Vec::new();
            collect_paths(tokens.into_iter().collect(), 0, &mut paths);
            let used = paths
                .iter()
                .filter_map(|p| target(file, p, module.crate_path, &nodes))
                .filter(|used| used != file)
                .collect();
            (file.clone(), used)
        })
        .collect()
}

/// Whether `tokens[i..]` starts with `::`.
fn path_separator(tokens: &[TokenTree], i: usize) -> bool {
    matches!(
        (tokens.get(i), tokens.get(i + 1)),
        (Some(TokenTree::Punct(a)), Some(TokenTree::Punct(b)))
            if a.as_char() == ':' && a.spacing() == Spacing::Joint && b.as_char() == ':'
    )
}

/// Every path in `tokens` (written in `depth` inline modules), use trees expanded: `use
/// super::{a::B, c}` gives `super::a::B` and `super::c`.
fn collect_paths(tokens: Vec<TokenTree>, depth: usize, out: &mut Vec<PathIn>) {
    let mut i = 0;
    while i < tokens.len() {
        match &tokens[i] {
            TokenTree::Ident(m) if m == "mod" => {
                if let (Some(TokenTree::Ident(_)), Some(TokenTree::Group(g))) =
                    (tokens.get(i + 1), tokens.get(i + 2))
                {
                    if g.delimiter() == Delimiter::Brace {
                        collect_paths(g.stream().into_iter().collect(), depth + 1, out);
                        i += 3;
                        continue;
                    }
                }
                i += 1;
            }
            TokenTree::Ident(_) => {
                let (paths, next) = path_at(&tokens, i);
                out.extend(paths.into_iter().map(|segments| PathIn { depth, segments }));
                i = next;
            }
            TokenTree::Group(g) => {
                collect_paths(g.stream().into_iter().collect(), depth, out);
                i += 1;
            }
            _ => i += 1,
        }
    }
}

/// The path (or, ending in a use tree's braces, the paths) starting at the identifier
/// `tokens[i]`, and the index after it.
fn path_at(tokens: &[TokenTree], mut i: usize) -> (Vec<Vec<String>>, usize) {
    let mut segments = vec![tokens[i].to_string()];
    i += 1;
    while path_separator(tokens, i) {
        match tokens.get(i + 2) {
            Some(TokenTree::Ident(next)) => {
                segments.push(next.to_string());
                i += 3;
            }
            Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Brace => {
                let inner: Vec<TokenTree> = g.stream().into_iter().collect();
                let paths = (inner.split(|t| matches!(t, TokenTree::Punct(p) if p.as_char() == ',')))
                    .filter(|element| matches!(element.first(), Some(TokenTree::Ident(_))))
                    .flat_map(|element| path_at(element, 0).0)
                    .map(|rest| segments.iter().cloned().chain(rest).collect())
                    .collect();
                return (paths, i + 3);
            }
            // `super::*`: everything of the module.
            Some(TokenTree::Punct(p)) if p.as_char() == '*' => {
                segments.push("*".to_owned());
                return (vec![segments], i + 3);
            }
            _ => break,
        }
    }
    (vec![segments], i)
}

/// The file of the directory that `path`, written in `file`, names, if any.
fn target(file: &str, path: &PathIn, crate_path: &[&str], nodes: &BTreeSet<String>) -> Option<String> {
    let segments = &path.segments;
    let supers = segments.iter().take_while(|s| *s == "super").count();
    // What follows the directory's module in the path, if the path goes through it.
    let within = match (supers, file) {
        // `super` from `mod.rs` leaves the directory; from an inline module, it stays in it.
        (0, _) if segments[0] == "crate" => {
            let through = segments.len() > crate_path.len() + 1
                && segments[1..=crate_path.len()]
                    .iter()
                    .zip(crate_path)
                    .all(|(s, c)| s == c);
            through.then(|| &segments[crate_path.len() + 1..])
        }
        (0, "mod") if path.depth == 0 && segments.len() > 1 => match segments[0] == "self" {
            true => Some(&segments[1..]),
            false => Some(&segments[..]),
        },
        (k, "mod") if k == path.depth && k > 0 => Some(&segments[k..]),
        (k, _) if k == path.depth + 1 && file != "mod" => Some(&segments[k..]),
        _ => None,
    }?;
    let first = within.first()?;
    match (nodes.contains(first), file) {
        (true, _) => Some(first.clone()),
        // An item of `mod.rs` (or all of them, `super::*`) named by a child.
        (false, f) if f != "mod" => Some("mod".to_owned()),
        (false, _) => None,
    }
}

/// The cycles among `uses` (each strongly connected set of files, as a chain that closes).
fn cycles(uses: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    let reaches = |from: &String, to: &String| {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from.clone()];
        while let Some(f) = stack.pop() {
            for g in uses.get(&f).into_iter().flatten() {
                if g == to {
                    return true;
                }
                if seen.insert(g.clone()) {
                    stack.push(g.clone());
                }
            }
        }
        false
    };
    let mut found: Vec<Vec<String>> = Vec::new();
    for file in uses.keys() {
        if found.iter().any(|c| c.contains(file)) || !reaches(file, file) {
            continue;
        }
        let together = (uses.keys())
            .filter(|g| reaches(file, g) && reaches(g, file))
            .cloned()
            .collect();
        found.push(together);
    }
    found
}

/// Fails naming every cycle among the files of `dir` (relative to the workspace), whose module
/// is `crate::<crate_path>`.
fn assert_one_way(dir: &str, crate_path: &[&str]) {
    let root = workspace_root().join(dir);
    let uses = uses(&ModuleDir {
        dir: &root,
        crate_path,
    });
    assert!(uses.len() > 1, "{dir}: no module files");
    let cycles = cycles(&uses);
    let described: Vec<String> = cycles
        .iter()
        .map(|files| {
            let edges: Vec<String> = files
                .iter()
                .flat_map(|f| {
                    (uses[f].iter())
                        .filter(|g| files.contains(g))
                        .map(move |g| format!("{f} → {g}"))
                })
                .collect();
            format!("{{{}}}: {}", files.join(", "), edges.join(", "))
        })
        .collect();
    assert!(
        cycles.is_empty(),
        "{dir}: files that use each other:\n{}",
        described.join("\n")
    );
}

#[test]
fn the_emitter_is_a_one_way_chain() {
    assert_one_way("codegen/src/generate/emit", &["generate", "emit"]);
}

#[test]
fn the_description_modules_are_a_one_way_chain() {
    assert_one_way("model/src/description", &["description"]);
}

/// The reading of uses, on small directories written here.
#[test]
fn uses_are_read_from_use_trees_paths_and_the_parent_module() {
    let dir = tempfile::tempdir().expect("dir");
    let write = |name: &str, text: &str| std::fs::write(dir.path().join(name), text).expect("write");
    write(
        "mod.rs",
        "mod a;\nmod b;\nmod c;\npub use a::A;\npub struct Top;\n",
    );
    write(
        "a.rs",
        "use super::{b::B, c};\n// super::c::D in a comment\npub struct A;\n\
         #[cfg(test)]\nmod tests { use super::*; }\n",
    );
    write(
        "b.rs",
        "pub struct B;\nfn f() -> crate::m::c::C { super::c::C }\n",
    );
    write("c.rs", "pub struct C;\nconst S: &str = \"super::a::A\";\n");
    let module = ModuleDir {
        dir: dir.path(),
        crate_path: &["m"],
    };
    let set = |names: &[&str]| names.iter().map(|n| n.to_string()).collect::<BTreeSet<_>>();
    let found = uses(&module);
    assert_eq!(found["mod"], set(&["a"]));
    assert_eq!(found["a"], set(&["b", "c"]));
    assert_eq!(found["b"], set(&["c"]));
    assert_eq!(found["c"], set(&[]));
    assert!(cycles(&found).is_empty());

    // A child using an item of `mod.rs`, which uses the child back.
    write("c.rs", "use super::Top;\npub struct C;\n");
    write(
        "mod.rs",
        "mod a;\nmod b;\nmod c;\npub struct Top;\nfn g() { c::C; }\n",
    );
    let found = uses(&module);
    assert_eq!(found["c"], set(&["mod"]));
    assert_eq!(cycles(&found), vec![vec!["c".to_owned(), "mod".to_owned()]]);

    // Back to the first through the crate's path: a → b → c → a.
    write("c.rs", "use crate::m::a::A;\npub struct C;\n");
    write("mod.rs", "mod a;\nmod b;\nmod c;\n");
    let found = uses(&module);
    assert_eq!(found["mod"], set(&[]));
    assert_eq!(
        cycles(&found),
        vec![vec!["a".to_owned(), "b".to_owned(), "c".to_owned()]]
    );
}
