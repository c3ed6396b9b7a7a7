//! Every command-line example in the README and in `docs/*.md` is run here, against the files shipped in
//! `examples/`, and must print exactly what the page shows: the documentation cannot drift from the program.
//!
//! An example is a ```` ```console ```` block: each `$ curvicast ARGS` line is a command, and the lines after it
//! (up to the next command or the block's end) are its standard output. `[..]` in an expected line matches any
//! text (for the figures that vary from run to run, such as timings). The commands run in a fresh directory that
//! holds a copy of `examples/`, so that what they write stays out of the repository.

use crate::support;

use std::path::{Path, PathBuf};

/// The pages whose examples run: the README and every page of `docs/`.
fn pages(root: &Path) -> Vec<PathBuf> {
    let mut pages = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

/// The (command, expected output lines) of every ```console block of `text`.
fn examples(text: &str) -> Vec<(String, Vec<String>)> {
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    let mut in_block = false;
    for line in text.lines() {
        if !in_block {
            in_block = line.trim_end() == "```console";
            continue;
        }
        if line.trim_end() == "```" {
            in_block = false;
        } else if let Some(cmd) = line.strip_prefix("$ ") {
            out.push((cmd.to_string(), Vec::new()));
        } else if let Some((_, expected)) = out.last_mut() {
            expected.push(line.to_string());
        } else {
            panic!("output before any command in a console block: {line}");
        }
    }
    assert!(!in_block, "a console block is not closed");
    out
}

/// Whether `got` matches `want`, in which `[..]` stands for any text.
fn matches(want: &str, got: &str) -> bool {
    let mut parts = want.split("[..]");
    let first = parts.next().unwrap_or("");
    let Some(mut rest) = got.strip_prefix(first) else {
        return false;
    };
    let parts: Vec<&str> = parts.collect();
    for (k, part) in parts.iter().enumerate() {
        if k + 1 == parts.len() {
            return rest.ends_with(part);
        }
        match rest.find(part) {
            Some(i) => rest = &rest[i + part.len()..],
            None => return false,
        }
    }
    rest.is_empty()
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let target = to.join(path.file_name().unwrap());
        if path.is_dir() {
            copy_dir(&path, &target);
        } else {
            std::fs::copy(&path, &target).unwrap();
        }
    }
}

#[test]
fn every_console_example_in_the_readme_and_the_docs_prints_what_the_page_shows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let work = tempfile::tempdir().unwrap();
    copy_dir(&root.join("examples"), &work.path().join("examples"));
    let mut ran = Vec::new();
    for page in pages(root) {
        let text = std::fs::read_to_string(&page).unwrap();
        let name = page.strip_prefix(root).unwrap().display().to_string();
        for (cmd, expected) in examples(&text) {
            let args: Vec<&str> = cmd.split_whitespace().collect();
            assert_eq!(
                args.first(),
                Some(&"curvicast"),
                "{name}: `{cmd}` is not a curvicast command"
            );
            let (code, out, err) = support::run_in(Some(work.path()), &args[1..], "");
            assert_eq!(code, 0, "{name}: `{cmd}` failed:\n{err}");
            let got: Vec<&str> = out.lines().collect();
            assert_eq!(got.len(), expected.len(), "{name}: `{cmd}` printed\n{out}");
            for (want, line) in expected.iter().zip(&got) {
                assert!(
                    matches(want, line),
                    "{name}: `{cmd}` printed\n{line}\nwhere the page shows\n{want}"
                );
            }
            ran.push(format!("{name}: {cmd}"));
        }
    }
    // The README has one example per subcommand that reads files.
    for sub in ["march", "pick", "render", "tessellate"] {
        let prefix = format!("README.md: curvicast {sub} ");
        assert!(
            ran.iter().any(|r| r.starts_with(&prefix)),
            "no README example of `{sub}`: {ran:#?}"
        );
    }
}

#[test]
fn the_wildcard_matches_any_text_and_nothing_else_is_loose() {
    assert!(matches("abc", "abc"));
    assert!(!matches("abc", "abcd"));
    assert!(matches("a[..]d", "abcd"));
    assert!(matches("[..]", "anything"));
    assert!(matches("{\"s\":[..],\"n\":3}", "{\"s\":0.25,\"n\":3}"));
    assert!(!matches("{\"s\":[..],\"n\":3}", "{\"s\":0.25,\"n\":4}"));
    assert!(!matches("a[..]d", "abce"));
}
