//! The `sporadic` command-line program.

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    return_freed_buffers_to_the_system();
    end_quietly_on_a_closed_pipe();
    cli::run()
}

/// Restores the default action of `SIGPIPE` (end the process) that the Rust runtime replaces
/// with "ignore": otherwise the program panics with "failed printing to stdout: Broken pipe"
/// when its reader goes away, as in `sporadic sdp solve FILE | head`, where every Unix tool
/// ends quietly.
#[cfg(unix)]
#[allow(unsafe_code)]
fn end_quietly_on_a_closed_pipe() {
    // SAFETY: `signal` sets the disposition of one signal to its default and touches no memory
    // of ours; it is called before the program starts any thread.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Other platforms have no `SIGPIPE`.
#[cfg(not(unix))]
fn end_quietly_on_a_closed_pipe() {}

/// Smallest allocation (256 KiB: a dense block of order ≥ 182) that glibc maps from the kernel
/// and unmaps when it is freed.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MMAP_THRESHOLD: libc::c_int = 256 << 10;

/// Makes the process's memory follow what the SDP solver holds. glibc serves a freed large
/// block's successors from its heap (its mmap threshold rises to the size of every mapped block
/// freed, up to 32 MiB), where the matrices of consecutive iterations fragment it and freed
/// blocks are never returned: on SDPLIB's maxG32 the peak resident memory was 1057 MiB for a
/// heap peak of about 490 MiB. A fixed threshold keeps every large block mapped and returned
/// on free, at the price of page faults on the next allocation (+8…40% time on the problems of
/// order 500–2000, none on the small ones, whose blocks stay below the threshold).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[allow(unsafe_code)]
fn return_freed_buffers_to_the_system() {
    // SAFETY: `mallopt` changes an allocator parameter and touches no memory of ours; it is
    // called before the program starts any thread.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
    }
}

/// Other platforms keep their allocator's defaults.
#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn return_freed_buffers_to_the_system() {}
