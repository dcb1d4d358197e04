//! SIGINT and SIGTERM: what a run has half-done on disk (an output set's staging folder, a commit
//! under way, the asset fetch's work folder and its download) is finished or removed before the
//! process ends. A signal handler may do almost nothing safely, so it only writes the signal's
//! number to a pipe; a thread reading the pipe waits for any commit under way ([`critical`]), runs
//! every clean-up registered with [`on_signal`], then ends the process by the same signal with its
//! default action, so the shell and the caller see the status they would have seen.
//!
//! Only the binary installs it ([`install`]): a program embedding the library keeps its own
//! signal handling, and the registrations cost nothing there.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::{Mutex, MutexGuard};

type Cleanup = Box<dyn FnOnce() + Send>;

struct Registry {
    next: u64,
    cleanups: BTreeMap<u64, Cleanup>,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    next: 0,
    cleanups: BTreeMap::new(),
});
/// Held by a commit while it moves files, and by the signal thread from the signal to the end.
static COMMIT: Mutex<()> = Mutex::new(());
/// The pipe's write end, for the handler; -1 until installed.
static PIPE: AtomicI32 = AtomicI32::new(-1);

fn lock<T>(m: &'static Mutex<T>) -> MutexGuard<'static, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// A clean-up that runs if a signal ends the process; dropping this unregisters it unrun.
#[must_use = "dropping the registration unregisters the clean-up"]
pub struct Registered(u64);

impl Drop for Registered {
    fn drop(&mut self) {
        lock(&REGISTRY).cleanups.remove(&self.0);
    }
}

/// Runs `cleanup` if SIGINT or SIGTERM ends the process while the returned value lives.
pub fn on_signal(cleanup: impl FnOnce() + Send + 'static) -> Registered {
    let mut r = lock(&REGISTRY);
    let id = r.next;
    r.next += 1;
    r.cleanups.insert(id, Box::new(cleanup));
    Registered(id)
}

/// Held while a commit moves files in: a signal waits for the guard, so the commit finishes first.
pub struct Critical(#[allow(dead_code)] MutexGuard<'static, ()>);

pub fn critical() -> Critical {
    Critical(lock(&COMMIT))
}

extern "C" fn handler(sig: libc::c_int) {
    let fd = PIPE.load(Ordering::Relaxed);
    if fd >= 0 {
        let byte = sig as u8;
        // SAFETY: write(2) is async-signal-safe; a full pipe only drops a repeated signal.
        unsafe { libc::write(fd, (&byte as *const u8).cast(), 1) };
    }
}

/// Catches SIGINT and SIGTERM for the rest of the process. Call once, early in `main`.
pub fn install() -> std::io::Result<()> {
    let mut fds = [0 as libc::c_int; 2];
    // SAFETY: a valid two-element array; close-on-exec keeps the pipe out of child processes.
    if unsafe { libc::pipe2(fds.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    let [read, write] = fds;
    PIPE.store(write, Ordering::Relaxed);
    std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || watch(read))?;
    for sig in [libc::SIGINT, libc::SIGTERM] {
        // SAFETY: a plain handler that only writes to a pipe; SA_RESTART keeps the run's system
        // calls from failing with EINTR while the clean-up runs.
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = handler as extern "C" fn(libc::c_int) as usize;
            action.sa_flags = libc::SA_RESTART;
            libc::sigemptyset(&mut action.sa_mask);
            if libc::sigaction(sig, &action, std::ptr::null_mut()) != 0 {
                return Err(std::io::Error::last_os_error());
            }
        }
    }
    Ok(())
}

/// The signal thread: on the first signal, the commit under way finishes, every clean-up runs,
/// and the process ends by that signal.
fn watch(read: libc::c_int) {
    let mut byte = 0u8;
    loop {
        // SAFETY: reading one byte into a local.
        let n = unsafe { libc::read(read, (&mut byte as *mut u8).cast(), 1) };
        if n == 1 {
            break;
        }
        if n == 0 || std::io::Error::last_os_error().kind() != std::io::ErrorKind::Interrupted {
            return;
        }
    }
    // Kept to the end: no commit starts after the signal.
    let _commit = lock(&COMMIT);
    let cleanups = std::mem::take(&mut lock(&REGISTRY).cleanups);
    for (_, cleanup) in cleanups.into_iter().rev() {
        cleanup();
    }
    let sig = byte as libc::c_int;
    // SAFETY: back to the default action, then the signal again: the process ends as if it had
    // never been caught (exit status 128 + sig in a shell).
    unsafe {
        libc::signal(sig, libc::SIG_DFL);
        libc::raise(sig);
    }
    std::process::exit(128 + sig);
}
