//! `polywear`: the command-line program (see `polywear --help`); everything is in `polywear-cli`.

fn main() -> std::process::ExitCode {
    polywear_cli::main()
}
