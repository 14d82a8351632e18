//! `opalray`: the command line of the opalray spectral renderer.
//!
//! Every subcommand reads a scene (a preset, a TOML file, flags on top), runs the stages it
//! needs and writes its files atomically. Errors are one line on stderr and exit code 2.

mod cmd;

use clap::{Parser, Subcommand};

/// mimalloc keeps freed memory for reuse: the passes allocate and free buffers of tens of MB
/// per frame, which the system allocator hands back to the kernel and then faults in again.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Spectral rendering of precious opal's play of colour.
#[derive(Parser)]
#[command(name = "opalray", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Grow the opal's cluster/void structure and draw the orientation map (paper fig. 9).
    Structure(cmd::structure::Args),
    /// Print a complete scene as TOML, to start a scene file from.
    Scene(cmd::scene::Args),
    /// Reflectance of one FCC cluster over wavelength and angle: peaks, colours, CSV, plot.
    Spectrum(cmd::spectrum::Args),
    /// Colour of a spectrum given as CSV: XYZ, xy, sRGB, hex.
    Color(cmd::color::Args),
    /// Render the opal to an image (paper figs. 10–11).
    Render(cmd::render::Args),
    /// Render the light sweep −60°…60° as a contact sheet and animation (paper fig. 11).
    Sweep(cmd::sweep::Args),
    /// Time every stage of the default render and report the medians.
    Bench(cmd::bench::Args),
}

fn main() {
    let cli = Cli::try_parse().unwrap_or_else(|err| {
        use clap::error::ErrorKind;
        if matches!(
            err.kind(),
            ErrorKind::DisplayHelp
                | ErrorKind::DisplayVersion
                | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
        ) {
            err.exit();
        }
        // clap explains a bad flag over several lines; keep its first, which names the flag.
        let text = err.to_string();
        let first = text.lines().next().unwrap_or("invalid arguments").trim();
        let first = first.strip_prefix("error: ").unwrap_or(first);
        eprintln!("error: {first} (see --help)");
        std::process::exit(2);
    });
    let result = match cli.command {
        Command::Structure(args) => cmd::structure::run(args),
        Command::Scene(args) => cmd::scene::run(args),
        Command::Spectrum(args) => cmd::spectrum::run(args),
        Command::Color(args) => cmd::color::run(args),
        Command::Render(args) => cmd::render::run(args),
        Command::Sweep(args) => cmd::sweep::run(args),
        Command::Bench(args) => cmd::bench::run(args),
    };
    if let Err(err) = result {
        eprintln!("error: {}", one_line(&err));
        std::process::exit(2);
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
