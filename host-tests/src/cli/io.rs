//! Input and output helpers shared by the subcommands: reading rays (from a file or stdin), the usage error that
//! exits with code 2, and the per-ray error line.

use crate::scenes::spec::RaySpec;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

/// An error that makes the command exit with code 2 after printing one line on stderr (and nothing on stdout).
#[derive(Debug)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// One line of a rays file: a ray, or why that line is not a ray (answered as `{"ray": i, "error": ...}`).
pub type RayLine = Result<RaySpec, String>;

/// Reads a JSON Lines rays file (`--rays FILE`) or standard input. Blank lines are skipped and do not count as
/// rays. A line that is not valid JSON of the ray shape becomes an `Err` for that ray only; an unreadable file is
/// a [`UsageError`].
pub fn read_rays(path: Option<&Path>) -> Result<Vec<RayLine>, UsageError> {
    let (name, reader): (String, Box<dyn Read>) = match path {
        Some(p) => {
            let f = std::fs::File::open(p)
                .map_err(|e| UsageError(format!("{}: cannot open rays file: {e}", p.display())))?;
            (p.display().to_string(), Box::new(f))
        }
        None => ("<stdin>".to_string(), Box::new(std::io::stdin())),
    };
    let mut out = Vec::new();
    for (n, line) in BufReader::new(reader).lines().enumerate() {
        let line =
            line.map_err(|e| UsageError(format!("{name}: line {}: cannot read: {e}", n + 1)))?;
        if line.trim().is_empty() {
            continue;
        }
        out.push(serde_json::from_str::<RaySpec>(&line).map_err(|e| format!("invalid ray: {e}")));
    }
    Ok(out)
}

/// The output line for a ray that could not be answered.
pub fn error_line(ray: usize, message: &str) -> String {
    serde_json::json!({"ray": ray, "error": message}).to_string()
}
