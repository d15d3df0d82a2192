//! The calling thread's own CPU clock. On a software device (lavapipe) the rasteriser's
//! threads share the CPU with the thread that prepares frames, so that thread's wall time
//! counts the time they take from it; its CPU clock counts its own work alone.

/// Milliseconds of CPU time the calling thread has used, where the platform has a
/// per-thread clock (Unix); `None` elsewhere.
pub fn thread_cpu_ms() -> Option<f64> {
    #[cfg(unix)]
    {
        let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
        // SAFETY: `t` is a valid timespec for the call to write; the clock id is a constant.
        let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
        (status == 0).then_some(t.tv_sec as f64 * 1e3 + t.tv_nsec as f64 * 1e-6)
    }
    #[cfg(not(unix))]
    {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn the_clock_counts_this_threads_work_and_not_its_sleep() {
        let start = thread_cpu_ms().expect("a thread clock on Unix");
        std::thread::sleep(std::time::Duration::from_millis(30));
        let slept = thread_cpu_ms().unwrap() - start;
        let busy_start = std::time::Instant::now();
        let mut x = 1u64;
        while busy_start.elapsed() < std::time::Duration::from_millis(30) {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
        }
        let worked = thread_cpu_ms().unwrap() - start - slept;
        assert!(slept < 10.0, "sleeping 30 ms used {slept} ms of CPU");
        assert!(worked > 5.0, "30 ms of work used only {worked} ms of CPU");
    }
}
