//! The exit-code contract of every command (docs/cli.md), and the failure that carries a
//! code and its message up to `main`.

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use lagrange::{Error, ErrorKind};

/// The exit codes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exit {
    /// The work was done.
    Success = 0,
    /// The user's input is wrong: the model, a flag, a value, a file name.
    Input = 1,
    /// Degenerate or unsupported mechanics (a singular mass matrix, conflicting constraints).
    Mechanics = 2,
    /// A simulation stopped before its end because the integration failed (rows kept).
    RunFailed = 3,
    /// lagrange disagrees with itself: a bug.
    Internal = 4,
    /// The output could not be written (a full disk, a closed stream).
    Output = 5,
}

impl From<Exit> for ExitCode {
    fn from(exit: Exit) -> ExitCode {
        ExitCode::from(exit as u8)
    }
}

/// A command that did not succeed: its code and what to print (already printed when empty).
#[derive(Debug)]
pub struct Failure {
    /// The exit code.
    pub code: Exit,
    /// The whole message (`error: …`, or rendered diagnostics).
    pub message: String,
}

impl Failure {
    /// The user's mistake; the message is printed after `error: `.
    pub fn input(message: impl std::fmt::Display) -> Failure {
        let message = format!("error: {message}");
        Failure {
            code: Exit::Input,
            message,
        }
    }

    /// A library error about the model file `path`.
    pub fn of(error: Error, path: &Path) -> Failure {
        let file = path.display().to_string();
        let message = error.render(&file, crate::commands::render_options());
        Failure::with(&error, message)
    }

    /// A library error about no file (an expression on its own).
    pub fn plain(error: Error) -> Failure {
        Failure::with(&error, format!("error: {error}"))
    }

    /// A library error about what a flag gave: `error: --set k2=1: …`.
    pub fn flag(flag: &str, error: Error) -> Failure {
        Failure::with(&error, format!("error: {flag} {error}"))
    }

    /// The code of `error`'s kind, and how to go past a work limit after its message.
    fn with(error: &Error, mut message: String) -> Failure {
        let code = match error.kind() {
            ErrorKind::Input => Exit::Input,
            ErrorKind::Internal => Exit::Internal,
            ErrorKind::Output => Exit::Output,
            _ => Exit::Mechanics,
        };
        if error.work_limit().is_some() {
            message.push_str(WORK_LIMIT_HELP);
        }
        Failure { code, message }
    }

    /// The same failure with `what: ` before its message (a flag's name).
    #[must_use]
    pub fn prefixed(mut self, what: &str) -> Failure {
        if let Some(rest) = self.message.strip_prefix("error: ") {
            self.message = format!("error: {what}: {rest}");
        }
        self
    }

    /// Prints the message and gives the exit code.
    pub fn report(self) -> ExitCode {
        if !self.message.is_empty() {
            let mut err = std::io::stderr().lock();
            let _ = writeln!(err, "{}", self.message.trim_end());
        }
        self.code.into()
    }
}

/// How to go past a work limit, after its message.
const WORK_LIMIT_HELP: &str =
    "\nhelp: `--work-limit 10` allows ten times as much symbolic work (terms, degree, operations)";

/// Writes `bytes` to standard output; a write error (a full disk) is [`Exit::Output`].
pub fn print(bytes: impl AsRef<[u8]>) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    out.write_all(bytes.as_ref())
        .and_then(|()| out.flush())
        .map_err(|e| {
            Failure::plain(Error::Write {
                what: "standard output".into(),
                reason: e.to_string(),
            })
        })
}

/// [`print`] with a line break.
pub fn println(text: &str) -> Result<(), Failure> {
    print(format!("{}\n", text.trim_end_matches('\n')))
}

/// Prints `bytes`, or writes them to `out` and says so.
pub fn emit(out: Option<&Path>, bytes: impl AsRef<[u8]>) -> Result<(), Failure> {
    let Some(out) = out else {
        return print(bytes);
    };
    lagrange::write_file(out, bytes.as_ref()).map_err(Failure::plain)?;
    println(&format!("wrote {}", out.display()))
}

/// Refuses an output file that is the model itself; says on stderr when an existing file is
/// replaced.
pub fn check_output(file: &Path, model: &Path) -> Result<(), Failure> {
    if lagrange::check_output(file, model).map_err(|e| Failure::of(e, model))? {
        eprintln!("replacing {}", file.display());
    }
    Ok(())
}
