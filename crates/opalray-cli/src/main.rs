//! `opalray`: the command line of the opalray spectral renderer.
//!
//! Every subcommand reads a scene (a preset, a TOML file, flags on top), runs the stages it
//! needs and writes its files atomically. Errors are one line on stderr and exit code 2.

mod anonymous;
mod cmd;
mod outputs;
mod stdio;

use clap::{Parser, Subcommand};

/// mimalloc keeps freed memory for reuse: the passes allocate and free buffers of tens of MB
/// per frame, which the system allocator hands back to the kernel and then faults in again.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Spectral rendering of precious opal's play of colour.
#[derive(Parser)]
#[command(name = "opalray", version, about, long_about = None, after_help = ENVIRONMENT_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The environment variables the command reads, shown under `--help`.
const ENVIRONMENT_HELP: &str = "Environment:
  OPALRAY_MAX_MEMORY_MB  the most memory a command plans for, MiB (64 to 16777216); a run
                         estimated to need more is refused before any work, naming the value
                         to lower. Unset: 80 % of this machine's memory.
  RAYON_NUM_THREADS      worker threads, 1 to 256. Unset: every core.
  OPALRAY_SIMD           portable, widest or auto: which copy of the inner loops runs.";

#[derive(Subcommand)]
enum Command {
    /// Draw a slice of the stone that is rendered, coloured by orientation (paper fig. 9).
    Structure(cmd::structure::Args),
    /// Print a complete scene as TOML, to start a scene file from.
    Scene(cmd::scene::Args),
    /// Reflectance of one FCC cluster over wavelength and angle: peaks, colours, CSV, plot.
    Spectrum(cmd::spectrum::Args),
    /// Colour of a spectrum given as CSV: XYZ, xy, sRGB, hex.
    Color(cmd::color::Args),
    /// Render the opal to an image (paper figs. 10–11).
    Render(cmd::render::Args),
    /// Render the play of colour as frames: the light swept (paper fig. 11), the stone rocked
    /// or turned, or the environment turned; a contact sheet and an animation.
    Sweep(Box<cmd::sweep::Args>),
    /// Time every stage of the default render and report the medians.
    Bench(cmd::bench::Args),
}

fn main() {
    if let Some(line) = dash_typed_flag(std::env::args_os().skip(1)) {
        stdio::note(format_args!("error: {} (see --help)", excerpt_words(&line)));
        std::process::exit(2);
    }
    let cli = Cli::try_parse().unwrap_or_else(|err| {
        use clap::error::ErrorKind;
        if err.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
            // No subcommand: the usage is the error, on stderr.
            stdio::note(format_args!("{}", err.render().to_string().trim_end()));
            std::process::exit(2);
        }
        if matches!(
            err.kind(),
            ErrorKind::DisplayHelp | ErrorKind::DisplayVersion
        ) {
            // clap's own `exit` ignores a failed stdout; a full device must not pass.
            match stdio::out_raw(&err.render().to_string()) {
                Ok(()) => std::process::exit(0),
                Err(e) if e.is_closed_pipe() => std::process::exit(0),
                Err(e) => {
                    stdio::note(format_args!("error: {e}"));
                    std::process::exit(2);
                }
            }
        }
        if let Some(line) = negative_for_flag(&err) {
            stdio::note(format_args!("error: {} (see --help)", excerpt_words(&line)));
            std::process::exit(2);
        }
        // clap explains a bad flag over several lines; keep its first, which names the flag
        // (a missing argument is named on the line after).
        let text = err.to_string();
        let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
        let mut first = lines.next().unwrap_or("invalid arguments").to_string();
        if first.ends_with(':') {
            if let Some(next) = lines.next() {
                first = format!("{first} {next}");
            }
        }
        // Keep clap's tip (`a similar argument exists: '--width'`) on the same line.
        if let Some(tip) = text.lines().map(str::trim).find(|l| l.starts_with("tip:")) {
            first = format!("{first}; {tip}");
        }
        let first = first.as_str();
        let first = first.strip_prefix("error: ").unwrap_or(first);
        stdio::note(format_args!("error: {} (see --help)", excerpt_words(first)));
        std::process::exit(2);
    });
    let result = cmd::common::check_environment().and_then(|()| match cli.command {
        Command::Structure(args) => cmd::structure::run(args),
        Command::Scene(args) => cmd::scene::run(args),
        Command::Spectrum(args) => cmd::spectrum::run(args),
        Command::Color(args) => cmd::color::run(args),
        Command::Render(args) => cmd::render::run(args),
        Command::Sweep(args) => cmd::sweep::run(*args),
        Command::Bench(args) => cmd::bench::run(args),
    });
    if let Err(err) = result {
        if err
            .downcast_ref::<stdio::StdoutFailed>()
            .is_some_and(stdio::StdoutFailed::is_closed_pipe)
        {
            // The reader has gone (`opalray scene | head -1`): nothing left to say.
            std::process::exit(0);
        }
        stdio::note(format_args!("error: {}", excerpt_words(&one_line(&err))));
        std::process::exit(2);
    }
}

/// clap takes `--frames -1` for a flag `-1` and names no flag; say which flag got a
/// negative number.
fn negative_for_flag(err: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if err.kind() != ErrorKind::UnknownArgument {
        return None;
    }
    let Some(ContextValue::String(bad)) = err.get(ContextKind::InvalidArg) else {
        return None;
    };
    bad.parse::<f64>().ok()?;
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == bad)?;
    let flag = args[..at].last().filter(|f| f.starts_with("--"))?;
    Some(format!(
        "{flag} {bad}: must not be negative; give a number from the range in --help"
    ))
}

/// Dashes a flag's `--` becomes when typed in a word processor or pasted from one: the em
/// dash, the en dash, the minus sign and the hyphen (Unicode).
const LOOKALIKE_DASHES: [char; 4] = ['\u{2014}', '\u{2013}', '\u{2212}', '\u{2010}'];

/// The first argument that starts with a dash other than the ASCII hyphen-minus followed by a
/// letter or a digit (`—width`, `−60`), as an error saying what to type instead: clap would
/// take `—width` for the scene file and name its value.
fn dash_typed_flag(args: impl Iterator<Item = std::ffi::OsString>) -> Option<String> {
    for arg in args {
        let arg = arg.to_string_lossy();
        if arg == "--" {
            return None;
        }
        let rest = arg.trim_start_matches(LOOKALIKE_DASHES);
        let Some(dash) = arg.chars().next().filter(|c| LOOKALIKE_DASHES.contains(c)) else {
            continue;
        };
        let typed: String = arg[..arg.len() - rest.len()].to_string();
        let name = format!("U+{:04X}", u32::from(dash));
        if rest.starts_with(|c: char| c.is_ascii_digit() || c == '.') {
            return Some(format!(
                "`{arg}`: starts with `{typed}` ({name}), not the ASCII minus; write -{rest}"
            ));
        }
        if rest.starts_with(|c: char| c.is_ascii_alphabetic()) {
            return Some(format!(
                "`{arg}`: starts with `{typed}` ({name}), not two hyphens; write --{rest}"
            ));
        }
    }
    None
}

/// Longest run of text without a space kept whole in an error line; longer runs (a
/// 50 MB key echoed by the parser) keep their start and end.
const MAX_WORD_CHARS: usize = 80;

/// Longest error line written whole.
const MAX_LINE_CHARS: usize = 500;

/// `line` with every word longer than [`MAX_WORD_CHARS`] cut to a short excerpt.
fn excerpt_words(line: &str) -> String {
    let line = line
        .split(' ')
        .map(|word| {
            let chars = word.chars().count();
            if chars <= MAX_WORD_CHARS {
                word.to_string()
            } else {
                let head: String = word.chars().take(40).collect();
                let tail: String = word.chars().skip(chars - 20).collect();
                format!("{head}…{tail} ({chars} characters)")
            }
        })
        .collect::<Vec<_>>()
        .join(" ");
    if line.chars().count() <= MAX_LINE_CHARS {
        line
    } else {
        let head: String = line.chars().take(MAX_LINE_CHARS - 20).collect();
        format!("{head}… (cut)")
    }
}

/// The error and its causes on one line, each cause once (an I/O error's text is often
/// repeated by the error wrapping it).
fn one_line(err: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in err.chain() {
        let text = cause.to_string().replace('\n', " ");
        if !line.contains(&text) {
            if !line.is_empty() {
                line.push_str(": ");
            }
            line.push_str(&text);
        }
    }
    line
}
