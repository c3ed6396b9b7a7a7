//! Input and output shared by the ray subcommands (`march`, `pick`): the usage error that exits with code 2, the
//! per-ray error line, and the streaming loop that reads rays and writes answers as they arrive.
//!
//! Streaming (command-line contract, "Rays"): a reader thread splits the rays file (or standard input) into
//! lines and hands them over through a bounded channel; the command answers them in windows — as many lines as
//! have already arrived, at most `window` — in parallel, writes the answers in input order and flushes them
//! before it waits for more input. So a ray piped in alone is answered before the next one is written, and memory
//! stays bounded whatever the number of rays: at most [`QUEUED_LINES`] lines queued, one window of answers, and
//! lines of at most [`MAX_LINE_BYTES`].
//!
//! What happens to bad input once answers have been written:
//! - a line that is not a ray (malformed JSON, a NaN, a missing field, a line too long) is that ray's
//!   `{"ray": i, "error": "line N column C: invalid ray: ..."}` line, with `N` the line's number in the file, and
//!   the other rays are answered (exit 0) — whether it is line 1 or line 1000;
//! - a file that cannot be opened is a usage error before anything is written (exit 2, nothing on stdout);
//! - a file that fails while being read (an I/O error after some answers) ends the command after the answers to
//!   the rays before the failure, with one line on stderr naming the file and the line (exit 2).
//!
//! Blank lines are skipped and do not count as rays; a UTF-8 byte-order mark at the start of the input and `\r`
//! line ends are accepted. An error on output ends the command with one line on stderr (exit 1), never a panic;
//! a closed pipe (`| head -1`) ends it silently with exit 0, as Unix filters do.

use super::OutputError;
use crate::formats::spec::RaySpec;
use std::io::{BufRead, BufReader, ErrorKind, IsTerminal, Read, Write};
use std::path::Path;
use std::sync::mpsc::{Receiver, SyncSender, TryRecvError, sync_channel};

/// An error that makes the command exit with code 2 after printing one line on stderr (and nothing on stdout
/// when it happens before the first answer).
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

/// The longest line read as a ray (a ray is about a hundred bytes); a longer line is an error for that ray and
/// is skipped without being kept in memory.
pub const MAX_LINE_BYTES: usize = 1 << 16;

/// How many lines the reader thread may read ahead of the answers.
pub const QUEUED_LINES: usize = 8192;

/// What the reader thread hands over: a non-blank line (its 0-based ray index, its 1-based line number in the
/// file and its bytes, `None` when it was too long), or the read error that ends the input.
enum Input {
    Line {
        ray: usize,
        line: u64,
        bytes: Option<Vec<u8>>,
    },
    Failed(String),
}

/// Parses one line of a rays file (`line` is its 1-based number, used in the message).
pub fn parse_ray_line(line: u64, bytes: Option<&[u8]>) -> RayLine {
    let Some(bytes) = bytes else {
        return Err(format!(
            "line {line}: invalid ray: longer than {MAX_LINE_BYTES} bytes"
        ));
    };
    serde_json::from_slice::<RaySpec>(bytes).map_err(|e| {
        // serde_json counts lines and columns within the one line it was given; say the file's line instead.
        let text = e.to_string();
        let suffix = format!(" at line {} column {}", e.line(), e.column());
        let what = text.strip_suffix(&suffix).unwrap_or(&text);
        if e.column() > 0 {
            format!("line {line} column {}: invalid ray: {what}", e.column())
        } else {
            format!("line {line}: invalid ray: {what}")
        }
    })
}

/// Reads lines until the end of the input or the receiver hangs up; blank lines are skipped, the byte-order mark
/// of line 1 and `\r` before `\n` removed.
fn read_lines(name: &str, mut reader: impl BufRead, tx: &SyncSender<Input>) {
    let mut ray = 0usize;
    let mut line = 0u64;
    let mut buf = Vec::new();
    loop {
        line += 1;
        buf.clear();
        let mut too_long = false;
        // Read up to the newline, keeping at most MAX_LINE_BYTES of it.
        let end = loop {
            let chunk = match reader.fill_buf() {
                Ok(c) => c,
                Err(e) if e.kind() == ErrorKind::Interrupted => continue,
                Err(e) => {
                    let _ = tx.send(Input::Failed(format!(
                        "{name}: line {line}: cannot read the rays: {e}"
                    )));
                    return;
                }
            };
            if chunk.is_empty() {
                break true;
            }
            let (take, found) = match chunk.iter().position(|&b| b == b'\n') {
                Some(k) => (k + 1, true),
                None => (chunk.len(), false),
            };
            if !too_long {
                let keep = &chunk[..take];
                if buf.len() + keep.len() > MAX_LINE_BYTES + 2 {
                    too_long = true;
                    buf.clear();
                } else {
                    buf.extend_from_slice(keep);
                }
            }
            reader.consume(take);
            if found {
                break false;
            }
        };
        if end && buf.is_empty() && !too_long {
            return;
        }
        let mut text: &[u8] = &buf;
        if line == 1 {
            text = text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(text);
        }
        text = text.strip_suffix(b"\n").unwrap_or(text);
        text = text.strip_suffix(b"\r").unwrap_or(text);
        if !too_long && text.iter().all(u8::is_ascii_whitespace) {
            if end {
                return;
            }
            continue;
        }
        let bytes = (!too_long && text.len() <= MAX_LINE_BYTES).then(|| text.to_vec());
        if tx.send(Input::Line { ray, line, bytes }).is_err() {
            return;
        }
        ray += 1;
        if end {
            return;
        }
    }
}

/// Opens the rays (`--rays FILE`, or standard input) and starts the reader thread. An unopenable file is a
/// [`UsageError`] naming it.
fn open_rays(path: Option<&Path>) -> Result<Receiver<Input>, UsageError> {
    let (name, reader): (String, Box<dyn Read + Send>) = match path {
        Some(p) => {
            let f = std::fs::File::open(p)
                .map_err(|e| UsageError(format!("{}: cannot open rays file: {e}", p.display())))?;
            (p.display().to_string(), Box::new(f))
        }
        None => ("<stdin>".to_string(), Box::new(std::io::stdin())),
    };
    let (tx, rx) = sync_channel(QUEUED_LINES);
    // Not scoped: when the command stops early (a closed output pipe) it must not wait for input that may never
    // come; the thread ends when its next line finds the receiver gone, or with the process.
    std::thread::Builder::new()
        .name("rays reader".into())
        .spawn(move || read_lines(&name, BufReader::with_capacity(1 << 16, reader), &tx))
        .map_err(|e| UsageError(format!("cannot start the rays reader: {e}")))?;
    Ok(rx)
}

/// How an answer is computed: `answer(ray_index, parsed_line, out)` writes that ray's complete output line
/// (with its `\n`) to `out`.
pub type Answer<'a> = dyn Fn(usize, RayLine, &mut dyn Write) -> std::io::Result<()> + Sync + 'a;

/// Whether an output error ends the command silently (a closed pipe) or with a message.
fn output_error(e: std::io::Error) -> Result<(), StreamError> {
    if e.kind() == ErrorKind::BrokenPipe {
        Ok(())
    } else {
        Err(StreamError::Output(OutputError(e)))
    }
}

/// Why [`stream_answers`] stopped: the rays could not be read (exit code 2), or the answers could not be written
/// (exit code 1; a closed pipe is not an error).
#[derive(Debug)]
pub enum StreamError {
    /// The rays file or standard input.
    Input(UsageError),
    /// Standard output.
    Output(OutputError),
}

impl std::fmt::Display for StreamError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StreamError::Input(e) => e.fmt(f),
            StreamError::Output(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for StreamError {}

impl StreamError {
    /// The output error, if that is what this is.
    pub fn output(&self) -> Option<&OutputError> {
        match self {
            StreamError::Input(_) => None,
            StreamError::Output(e) => Some(e),
        }
    }
}

impl From<UsageError> for StreamError {
    fn from(e: UsageError) -> Self {
        StreamError::Input(e)
    }
}

/// A count of answered rays on stderr, shown once a run passes 10 000 rays and only when stderr is a terminal.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
    label: &'static str,
}

impl Progress {
    fn update(&mut self, answered: usize) {
        if self.bar.is_none() && answered >= 10_000 && std::io::stderr().is_terminal() {
            let pb = indicatif::ProgressBar::with_draw_target(
                None,
                indicatif::ProgressDrawTarget::stderr(),
            );
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{spinner} {msg}: {human_pos} rays answered",
            ) {
                pb.set_style(style);
            }
            pb.set_message(self.label);
            self.bar = Some(pb);
        }
        if let Some(pb) = &self.bar {
            pb.set_position(answered as u64);
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(pb) = &self.bar {
            pb.finish_and_clear();
        }
    }
}

/// Streams the rays of `path` (standard input when `None`) through `answer` and writes the answers to `out` in
/// input order (see the module docs for the rules).
///
/// `window` is the most rays answered at once: with `window > 1` each window's answers are computed in parallel
/// into memory and then written; with `window == 1` the rays are answered one after the other straight into the
/// (buffered) output, so that an answer of any length streams out with bounded memory.
pub fn stream_answers(
    path: Option<&Path>,
    out: &mut dyn Write,
    window: usize,
    label: &'static str,
    answer: &Answer<'_>,
) -> Result<(), StreamError> {
    use rayon::prelude::*;
    let rx = open_rays(path)?;
    let mut out = std::io::BufWriter::with_capacity(1 << 16, out);
    let window = window.max(1);
    let mut progress = Progress { bar: None, label };
    let mut answered = 0usize;
    let mut batch: Vec<(usize, u64, Option<Vec<u8>>)> = Vec::with_capacity(window);
    let mut failed = None;
    loop {
        // Wait for one line, then take the ones that have already arrived, up to the window.
        batch.clear();
        let mut ended = false;
        match rx.recv() {
            Ok(Input::Line { ray, line, bytes }) => batch.push((ray, line, bytes)),
            Ok(Input::Failed(m)) => failed = Some(m),
            Err(_) => ended = true,
        }
        while failed.is_none() && !ended && batch.len() < window {
            match rx.try_recv() {
                Ok(Input::Line { ray, line, bytes }) => batch.push((ray, line, bytes)),
                Ok(Input::Failed(m)) => failed = Some(m),
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => ended = true,
            }
        }
        let n = batch.len();
        let written = if window == 1 {
            batch.drain(..).try_for_each(|(ray, line, bytes)| {
                answer(ray, parse_ray_line(line, bytes.as_deref()), &mut out)
            })
        } else {
            let texts: Vec<Vec<u8>> = batch
                .par_drain(..)
                .map(|(ray, line, bytes)| {
                    let mut text = Vec::with_capacity(256);
                    // Writing into a Vec cannot fail.
                    let _ = answer(ray, parse_ray_line(line, bytes.as_deref()), &mut text);
                    text
                })
                .collect();
            texts.iter().try_for_each(|t| out.write_all(t))
        };
        answered += n;
        if let Err(e) = written.and_then(|()| out.flush()) {
            return output_error(e);
        }
        progress.update(answered);
        if let Some(m) = failed {
            return Err(UsageError(m).into());
        }
        if ended {
            return Ok(());
        }
    }
}

/// The output line (without its `\n`) for a ray that could not be answered.
pub fn error_line(ray: usize, message: &str) -> String {
    serde_json::json!({"ray": ray, "error": message}).to_string()
}
