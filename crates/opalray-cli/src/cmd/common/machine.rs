//! What the machine reports of a run: this process's peak memory, and the processor time
//! stolen by the hypervisor while it ran (`bench`).

/// Peak resident memory of this process so far, MiB, where the system reports it.
pub fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// The machine's processor time so far, all processors together (`/proc/stat`, in clock
/// ticks): `(total, stolen)`, stolen being the time a virtual processor was ready to run
/// while the hypervisor ran something else on its core. `None` where the system does not
/// report it.
pub fn cpu_ticks() -> Option<(u64, u64)> {
    parse_cpu_ticks(&std::fs::read_to_string("/proc/stat").ok()?)
}

/// [`cpu_ticks`] from the text of `/proc/stat`: the first line's user, nice, system, idle,
/// iowait, irq, softirq and steal times (guest time is already counted in user time).
fn parse_cpu_ticks(stat: &str) -> Option<(u64, u64)> {
    let line = stat.lines().next()?.strip_prefix("cpu ")?;
    let ticks: Vec<u64> = line
        .split_whitespace()
        .take(8)
        .map(str::parse)
        .collect::<Result<_, _>>()
        .ok()?;
    (ticks.len() == 8).then(|| (ticks.iter().sum(), ticks[7]))
}

/// The share of the machine's processor time stolen between two [`cpu_ticks`] readings, or
/// `None` if either is missing or no time passed.
pub fn stolen_share(before: Option<(u64, u64)>, after: Option<(u64, u64)>) -> Option<f64> {
    let ((t0, s0), (t1, s1)) = (before?, after?);
    (t1 > t0).then(|| s1.saturating_sub(s0) as f64 / (t1 - t0) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stolen_time_is_the_steal_column_over_the_first_eight() {
        // A line as Linux writes it: user nice system idle iowait irq softirq steal guest
        // guest_nice; the total is the first eight (guest time is inside user time).
        let stat = "cpu  100 0 20 600 5 0 3 72 9 0\ncpu0 50 0 10 300 2 0 1 36 4 0\n";
        assert_eq!(parse_cpu_ticks(stat), Some((800, 72)));
        assert_eq!(parse_cpu_ticks("cpu0 1 2 3 4 5 6 7 8\n"), None);
        assert_eq!(parse_cpu_ticks("cpu  1 2 3\n"), None);
        let share = stolen_share(Some((800, 72)), Some((1800, 322))).unwrap();
        assert!((share - 0.25).abs() < 1e-12, "{share}");
        assert_eq!(stolen_share(Some((800, 72)), Some((800, 72))), None);
        assert_eq!(stolen_share(None, Some((800, 72))), None);
    }
}
