//! The tools behind `glview bench` and `glview bench --soak`: benchmarks and the leak soak.
//! They are part of the command-line program, not of the library: they reach the library
//! only through its public API, like any other program built on it.
pub mod bench;
pub mod soak;

/// `glview bench`'s own command line.
#[derive(Debug, clap::Parser)]
#[command(
    name = "glview bench",
    about = "Benchmarks and the leak soak (README, Benchmarks)."
)]
pub struct BenchCli {
    /// Load, render and drop the scene this many times in one context (leak soak).
    #[arg(long)]
    pub soak: Option<u32>,
    #[command(flatten)]
    pub bench: bench::BenchArgs,
}

/// Runs `glview bench WORDS` with the program's picture options `args` (the soak's model).
pub fn run_bench(args: &glview::options::Options, words: &[String]) -> glview::Result<()> {
    use clap::Parser;
    let cli = BenchCli::try_parse_from(
        std::iter::once("glview bench".to_string()).chain(words.iter().cloned()),
    )
    .unwrap_or_else(|e| e.exit());
    match cli.soak {
        Some(rounds) => soak::run(args, rounds),
        None => bench::run(&cli.bench),
    }
}
