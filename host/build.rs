//! The git commit this build comes from, for the provenance block of every
//! output (src/provenance.rs): `SWIMBOT_GIT_COMMIT`, with `-dirty` when
//! tracked files differ from it. Outside a git checkout (a tarball, a
//! crates.io build) or without git, nothing is set and outputs say
//! `unknown`; a packager may set SWIMBOT_GIT_COMMIT itself.

use std::path::Path;
use std::process::Command;

fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(dir)
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    Some(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn main() {
    println!("cargo:rerun-if-env-changed=SWIMBOT_GIT_COMMIT");
    // Sources: a change to them can make the tree dirty.
    for p in ["src", "data", "Cargo.toml", "../shared/src"] {
        println!("cargo:rerun-if-changed={p}");
    }
    if let Ok(given) = std::env::var("SWIMBOT_GIT_COMMIT") {
        println!("cargo:rustc-env=SWIMBOT_GIT_COMMIT={given}");
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let Some(commit) = git(dir, &["rev-parse", "HEAD"]) else {
        return;
    };
    // A commit or a checkout moves HEAD or the branch it points to.
    let mut watched = vec!["HEAD".to_string(), "packed-refs".to_string()];
    watched.extend(git(dir, &["symbolic-ref", "-q", "HEAD"]));
    for w in watched {
        // A missing file would make cargo rerun this script on every build.
        if let Some(p) = git(dir, &["rev-parse", "--git-path", &w]).map(|p| dir.join(p)) {
            if p.exists() {
                println!("cargo:rerun-if-changed={}", p.display());
            }
        }
    }
    let dirty =
        git(dir, &["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
    let suffix = if dirty { "-dirty" } else { "" };
    println!("cargo:rustc-env=SWIMBOT_GIT_COMMIT={commit}{suffix}");
}
