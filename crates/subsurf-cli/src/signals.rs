//! Stopping cleanly when interrupted: on SIGINT, SIGTERM or SIGHUP the temporary files of
//! outputs being written and the directories this run created (still empty) are removed,
//! then the process ends as the signal's default action ends it.

/// Starts a thread that waits for SIGINT, SIGTERM and SIGHUP and cleans up when one comes
/// (nothing where signals are not Unix's, or when the handlers cannot be installed).
pub fn clean_up_on_signals() {
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
            return;
        };
        std::thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                subsurf::io::remove_temporary_files();
                crate::output::remove_created_dirs();
                // Ends the process with the signal (its default action), as if no handler
                // had been installed; the exit status below only if that fails.
                let _ = signal_hook::low_level::emulate_default_handler(signal);
                std::process::exit(128 + signal);
            }
        });
    }
}
