//! What a long run prints while it works (rank 0, stdout): a line at the
//! start of each long phase, and while iterating a line every few seconds.
//! A run shorter than [`LONG_RUN`] prints nothing extra; a phase known in
//! advance to be long (a large mesh to generate or read) says so at once.
//! A phase that turns long (a factorization) is named, with the time it
//! started, by a watcher thread once the run has lasted [`LONG_RUN`].
//! `-ubr_monitor` prints every iteration instead.

use std::io::Write as _;
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// A run is long once it has taken this many seconds.
pub const LONG_RUN: f64 = 2.0;
/// Seconds between two progress lines while iterating.
pub const PERIOD: f64 = 5.0;

/// The clock of the run, and whether this rank prints.
static START: OnceLock<(Instant, bool)> = OnceLock::new();

/// The current phase and what has been printed.
struct State {
    /// The phase's line, when it started (seconds), whether printed.
    phase: Option<(String, f64, bool)>,
    /// When the last iteration line was printed.
    last: Option<Instant>,
}

static STATE: Mutex<State> = Mutex::new(State {
    phase: None,
    last: None,
});

/// Starts the clock (once per run); only `root` prints, and only it runs
/// the watcher (none when no thread can be started, e.g. under a memory
/// limit that leaves no room for its stack: the run itself then decides).
pub fn start(root: bool) {
    if START.set((Instant::now(), root)).is_ok() && root {
        let _ = std::thread::Builder::new().spawn(|| loop {
            std::thread::sleep(Duration::from_millis(200));
            if elapsed() > LONG_RUN {
                with_state(|s| {
                    if let Some((line, t, printed @ false)) = &mut s.phase {
                        *printed = true;
                        emit(*t, line);
                    }
                });
            }
        });
    }
}

fn elapsed() -> f64 {
    START.get().map_or(0.0, |s| s.0.elapsed().as_secs_f64())
}

fn root() -> bool {
    START.get().is_some_and(|s| s.1)
}

fn with_state<T>(f: impl FnOnce(&mut State) -> T) -> Option<T> {
    STATE.lock().ok().map(|mut s| f(&mut s))
}

fn emit(t: f64, line: &str) {
    println!("[{t:7.1} s] {line}");
    let _ = std::io::stdout().flush();
}

/// The start of a phase: printed at once when the run is already long or
/// the phase is `expected_long`, else by the watcher if it turns long.
/// Every rank keeps its phase (for [`current`]); rank 0 prints it.
pub fn phase(expected_long: bool, line: impl FnOnce() -> String) {
    let (line, t) = (line(), elapsed());
    let now = root() && (expected_long || t > LONG_RUN);
    with_state(|s| {
        if now {
            emit(t, &line);
        }
        s.phase = Some((line, t, now));
    });
}

/// The phase this rank is in ("assembling and factorizing (N unknowns)",
/// "iterating", ...), if one has started.
pub fn current() -> Option<String> {
    with_state(|s| s.phase.as_ref().map(|p| p.0.clone())).flatten()
}

/// The end of the phases (before the summary): nothing more to announce.
pub fn finish() {
    with_state(|s| s.phase = None);
}

/// While iterating: printed when the run is long and [`PERIOD`] seconds
/// have passed since the last such line.
pub fn tick(line: impl FnOnce() -> String) {
    if !root() || elapsed() <= LONG_RUN {
        return;
    }
    let due = with_state(|s| {
        let due = s.last.is_none_or(|t| t.elapsed().as_secs_f64() >= PERIOD);
        if due {
            s.last = Some(Instant::now());
        }
        due
    });
    if due == Some(true) {
        emit(elapsed(), &line());
    }
}
