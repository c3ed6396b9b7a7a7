//! The kernel denies `clippy::arithmetic_side_effects`, but `clippy.toml` exempts the type names `T` and `Self`
//! (arithmetic on the kernel's scalar, an IEEE float whose arithmetic never panics). Clippy matches those names,
//! not the bound, so a `T` bound only by `Add` (an integer, say) would do unchecked arithmetic. This test holds
//! the exemption to what it is for, by reading the kernel's sources:
//!
//! * every generic parameter named `T` (in an `impl`, `fn`, `struct`, `enum` or `trait` header, or a `where`
//!   clause) is either unbounded (no arithmetic possible) or bound by `Real`, or only by traits that bring no
//!   arithmetic (`Copy`, `Clone`, `Debug`, `PartialEq`, ...);
//! * no trait of the kernel other than `Real` has arithmetic supertraits (so that `Self` in a trait's default
//!   methods is a `Real`).

use std::path::{Path, PathBuf};

/// Bounds that give a type no arithmetic.
const INERT: &[&str] = &[
    "Copy",
    "Clone",
    "Debug",
    "core::fmt::Debug",
    "Display",
    "PartialEq",
    "Eq",
    "PartialOrd",
    "Ord",
    "Hash",
    "Default",
    "Sized",
    "?Sized",
    "Send",
    "Sync",
    "'static",
];

/// Operator traits: a trait bound by one of these permits arithmetic.
const OPS: &[&str] = &[
    "Add", "Sub", "Mul", "Div", "Rem", "Neg", "Shl", "Shr", "BitAnd", "BitOr", "BitXor", "Sum",
    "Product",
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The text inside the angle brackets that open at byte `open` (nested brackets kept; `->` is not a bracket).
fn bracketed(s: &str, open: usize) -> Option<&str> {
    let b = s.as_bytes();
    let mut depth = 0i32;
    for (i, &c) in b.iter().enumerate().skip(open) {
        match c {
            b'<' => depth += 1,
            b'>' if i > 0 && b[i - 1] == b'-' => {}
            b'>' => {
                depth -= 1;
                if depth == 0 {
                    return Some(&s[open + 1..i]);
                }
            }
            b'{' | b';' => return None,
            _ => {}
        }
    }
    None
}

/// Splits at commas outside brackets and parentheses.
fn top_level(s: &str, sep: char) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut depth, mut start) = (0i32, 0);
    for (i, c) in s.char_indices() {
        match c {
            '<' | '(' | '[' => depth += 1,
            '>' if !s[..i].ends_with('-') => depth -= 1,
            ')' | ']' => depth -= 1,
            c if c == sep && depth == 0 => {
                out.push(&s[start..i]);
                start = i + c.len_utf8();
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

/// The bounds of `param` in a generic parameter list or where clause, if it names `param`.
fn bounds_of<'a>(entry: &'a str, param: &str) -> Option<Vec<&'a str>> {
    let e = entry.trim();
    let rest = e.strip_prefix(param)?;
    let rest = rest.trim_start();
    if rest.is_empty() {
        return Some(Vec::new());
    }
    let rest = rest.strip_prefix(':')?;
    Some(
        top_level(rest, '+')
            .into_iter()
            .map(str::trim)
            .filter(|b| !b.is_empty())
            .collect(),
    )
}

/// The name of a bound without its generic arguments (`Add<Output = T>` is `Add`).
fn trait_name(bound: &str) -> &str {
    let b = bound.split('<').next().unwrap_or(bound).trim();
    b.rsplit("::").next().unwrap_or(b)
}

/// What is wrong with a list of bounds on `T`, if anything.
fn check_t(bounds: &[&str]) -> Option<String> {
    if bounds.is_empty() || bounds.iter().any(|b| trait_name(b) == "Real") {
        return None;
    }
    let foreign: Vec<&&str> = bounds
        .iter()
        .filter(|b| !INERT.contains(b) && !INERT.contains(&trait_name(b)))
        .collect();
    (!foreign.is_empty()).then(|| format!("T bound by {foreign:?} without Real"))
}

/// Every violation in one file's text, as `line: message`.
fn violations(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let line_of = |at: usize| text[..at].matches('\n').count() + 1;
    // Generic parameter lists of item headers.
    for kw in ["impl", "fn ", "struct ", "enum ", "trait "] {
        for (at, _) in text.match_indices(kw) {
            // A keyword, not part of a longer word.
            if at > 0 && text.as_bytes()[at - 1].is_ascii_alphanumeric() {
                continue;
            }
            let after = &text[at + kw.len()..];
            if kw == "impl" && after.starts_with(|c: char| c.is_alphanumeric() || c == '_') {
                continue; // `implements`, not `impl`
            }
            let skip = after
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ' '))
                .unwrap_or(after.len());
            if !after[skip..].starts_with('<') {
                continue;
            }
            let open = at + kw.len() + skip;
            let Some(params) = bracketed(text, open) else {
                continue;
            };
            for entry in top_level(params, ',') {
                if let Some(m) = bounds_of(entry, "T").and_then(|b| check_t(&b)) {
                    out.push(format!("{}: {m}", line_of(open)));
                }
            }
        }
    }
    // Where clauses.
    for (at, _) in text.match_indices("where") {
        let b = text.as_bytes();
        let word = (at == 0 || !b[at - 1].is_ascii_alphanumeric())
            && b.get(at + 5).is_some_and(|c| c.is_ascii_whitespace());
        if !word {
            continue;
        }
        let rest = &text[at + 5..];
        let end = rest.find(['{', ';']).unwrap_or(rest.len());
        for entry in top_level(&rest[..end], ',') {
            if let Some(m) = bounds_of(entry, "T").and_then(|b| check_t(&b)) {
                out.push(format!("{}: {m} (where clause)", line_of(at)));
            }
        }
    }
    // Traits with arithmetic supertraits.
    for (at, _) in text.match_indices("trait ") {
        let rest = &text[at + 6..];
        let name_end = rest
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        let name = &rest[..name_end];
        let header = &rest[..rest.find('{').unwrap_or(rest.len())];
        if name == "Real" || name.is_empty() || !header[name_end..].trim_start().starts_with(':') {
            continue;
        }
        let supers = &header[name_end..];
        let supers = &supers[supers.find(':').unwrap() + 1..];
        let supers = supers.split("where").next().unwrap_or(supers);
        for s in top_level(supers, '+') {
            if OPS
                .iter()
                .any(|op| trait_name(s).trim_end_matches("Assign") == *op)
            {
                out.push(format!(
                    "{}: trait {name} has the arithmetic supertrait {}",
                    line_of(at),
                    s.trim()
                ));
            }
        }
    }
    out
}

#[test]
fn generic_arithmetic_in_the_kernel_goes_through_real() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../kernel/src");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    files.sort();
    assert!(
        files.len() > 20,
        "kernel sources not found at {}",
        root.display()
    );
    let mut bad = Vec::new();
    let mut generic_items = 0;
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        generic_items += text.matches("<T: Real").count();
        for v in violations(&text) {
            bad.push(format!("{}:{v}", f.display()));
        }
    }
    // The scan must see the kernel's generic code, or it checks nothing.
    assert!(
        generic_items > 100,
        "{generic_items} `<T: Real` headers seen"
    );
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn the_scan_finds_a_t_bound_only_by_add() {
    // What the test above must reject, and what it must accept.
    let bad = [
        "fn double<T: Copy + core::ops::Add<Output = T>>(x: T) -> T { x + x }",
        "impl<T: Add<Output = T>> Foo<T> { }",
        "fn f<T>(x: T) -> T where T: Mul<Output = T> + Copy { x * x }",
        "pub trait Counter: Copy + AddAssign { }",
        "struct S<T: num_traits::PrimInt>(T);",
    ];
    for src in bad {
        assert_eq!(violations(src).len(), 1, "{src}: {:?}", violations(src));
    }
    let good = [
        "fn double<T: Real>(x: T) -> T { x + x }",
        "impl<T: Real, const N: usize> Foo<T, N> { }",
        "impl<T> Node<T> { fn rows(&self) -> u32 { 0 } }",
        "fn comp<T: Copy>(v: V3<T>, k: usize) -> T { v.x }",
        "fn f<T>(x: T) -> T where T: Real { x * x }",
        "pub trait TerrainStorage<T: Real> { }",
        "fn g() -> Result<u32, E> { Ok(1) }",
    ];
    for src in good {
        assert!(violations(src).is_empty(), "{src}: {:?}", violations(src));
    }
}
