//! Embeds the commit granflow is built from (`GRANFLOW_COMMIT`: `git describe`-like short hash,
//! `-dirty` with uncommitted changes, "unknown" outside a git checkout) for provenance.
//!
//! The script reruns when the commit or the tree can have changed: the files git keeps HEAD,
//! the branch and the index in (asked from git, so that a linked worktree, whose `.git` is a
//! file, watches its own), and the sources (an unstaged edit makes the build dirty). Without
//! them a build sharing its target directory with another checkout kept that checkout's stamp.

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn main() {
    let commit = match git(&["rev-parse", "--short=12", "HEAD"]) {
        Some(hash) if !hash.is_empty() => {
            let dirty = git(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            if dirty { format!("{hash}-dirty") } else { hash }
        }
        _ => "unknown".to_string(),
    };
    println!("cargo:rustc-env=GRANFLOW_COMMIT={commit}");
    // the files that move with a commit, a checkout or staged edits, wherever git keeps them
    let mut watched: Vec<String> = ["HEAD", "index", "packed-refs"]
        .iter()
        .filter_map(|f| git(&["rev-parse", "--git-path", f]))
        .collect();
    if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"])
        && let Some(path) = git(&["rev-parse", "--git-path", &branch])
    {
        watched.push(path);
    }
    for path in watched {
        if std::path::Path::new(&path).exists() {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    // edits of tracked files not yet staged change the dirty flag
    for dir in ["src", "tests", "Cargo.toml", "Cargo.lock"] {
        println!("cargo:rerun-if-changed={dir}");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
