//! How much memory one buffer derived from input may take: sizes read from
//! files and arguments (film, EXR and PNG dimensions, blur kernels) are
//! multiplied with checked arithmetic and compared with this budget before
//! anything is allocated, so an absurd size is an error naming the limit
//! rather than a "capacity overflow" panic or an abort in the allocator.
//!
//! The budget is half of the memory this process may use: the machine's
//! physical memory (MemTotal in /proc/meminfo) or, where smaller, the
//! limit of its control group (a container's or a batch job's: cgroup v2
//! `memory.max`, v1 `memory.limit_in_bytes`); 8 GiB where neither can be
//! read. The environment
//! variable `SCOTOPIA_MEMORY_LIMIT` (bytes, or with a K/M/G/T suffix) sets it
//! instead. Independently, one image may have at most 2³¹ pixels.

use std::sync::OnceLock;

/// The most pixels one image may have (2³¹: indices fit an i32).
pub const MAX_PIXELS: u64 = 1 << 31;

/// The budget where physical memory cannot be read.
const FALLBACK_BYTES: u64 = 8 << 30;

/// A buffer that would not fit: what it is, the bytes it needs (`None`
/// where even the count overflows), and the limit.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what} {}; the limit is {limit}", needs(*.bytes))]
pub struct TooLarge {
    pub what: String,
    pub bytes: Option<u128>,
    /// The limit, in words ("160.0 GiB (… bytes), half of this machine's
    /// memory").
    pub limit: String,
}

fn needs(bytes: Option<u128>) -> String {
    match bytes {
        Some(b) => format!("would need {}", human_u128(b)),
        None => "would need more bytes than a 128-bit count holds".into(),
    }
}

/// `b` bytes in binary units, e.g. "3.5 GiB (3758096384 bytes)".
pub fn human(b: u64) -> String {
    human_u128(b as u128)
}

fn human_u128(b: u128) -> String {
    const UNITS: [&str; 7] = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let mut v = b as f64;
    let mut u = 0;
    while v >= 1024.0 && u + 1 < UNITS.len() {
        v /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{b} bytes")
    } else {
        format!("{v:.1} {} ({b} bytes)", UNITS[u])
    }
}

/// The memory budget for one buffer, in bytes, and where it comes from.
pub fn memory_limit() -> (u64, &'static str) {
    static LIMIT: OnceLock<(u64, &'static str)> = OnceLock::new();
    *LIMIT.get_or_init(|| {
        if let Some(b) = std::env::var("SCOTOPIA_MEMORY_LIMIT")
            .ok()
            .and_then(|v| parse_bytes(&v))
        {
            return (b, "set by SCOTOPIA_MEMORY_LIMIT");
        }
        let total = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|t| mem_total(&t));
        let group = std::fs::read_to_string("/proc/self/cgroup")
            .ok()
            .and_then(|t| cgroup_limit(&t, |p| std::fs::read_to_string(p).ok()));
        match (total, group) {
            (Some(t), Some(g)) if g < t => (g / 2, "half of this control group's memory limit"),
            (Some(t), _) => (t / 2, "half of this machine's memory"),
            (None, Some(g)) => (g / 2, "half of this control group's memory limit"),
            (None, None) => (FALLBACK_BYTES, "physical memory unknown"),
        }
    })
}

/// The smallest memory limit of this process's control groups, from the
/// text of /proc/self/cgroup; `read` reads a file (a parameter, for tests).
/// Both the group's own path and the mount's root are looked at, as a
/// container often sees its group at the root.
fn cgroup_limit(cgroups: &str, read: impl Fn(&str) -> Option<String>) -> Option<u64> {
    let mut files = vec![
        "/sys/fs/cgroup/memory.max".to_string(),
        "/sys/fs/cgroup/memory/memory.limit_in_bytes".to_string(),
    ];
    for line in cgroups.lines() {
        let mut parts = line.splitn(3, ':');
        let (_, controllers, path) = (parts.next(), parts.next(), parts.next());
        let path = path.unwrap_or("").trim_end_matches('/');
        match controllers {
            Some("") => files.push(format!("/sys/fs/cgroup{path}/memory.max")),
            Some(c) if c.split(',').any(|c| c == "memory") => {
                files.push(format!("/sys/fs/cgroup/memory{path}/memory.limit_in_bytes"))
            }
            _ => {}
        }
    }
    files
        .iter()
        .filter_map(|f| read(f)?.trim().parse::<u64>().ok())
        // "max" (v2) does not parse; v1 writes "no limit" as ~2^63.
        .filter(|&b| b > 0 && b < 1 << 62)
        .min()
}

/// MemTotal from the text of /proc/meminfo, in bytes.
fn mem_total(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// "123", "64K", "8G", "1.5T" → bytes.
fn parse_bytes(text: &str) -> Option<u64> {
    let t = text.trim();
    let (num, scale) = match t.char_indices().last()? {
        (i, 'K' | 'k') => (&t[..i], 1u64 << 10),
        (i, 'M' | 'm') => (&t[..i], 1 << 20),
        (i, 'G' | 'g') => (&t[..i], 1 << 30),
        (i, 'T' | 't') => (&t[..i], 1 << 40),
        _ => (t, 1),
    };
    let v: f64 = num.trim().parse().ok()?;
    (v.is_finite() && v > 0.0 && v * (scale as f64) < u64::MAX as f64)
        .then_some((v * scale as f64) as u64)
}

/// Checks that `count` elements of `element_bytes` each fit the budget
/// `limit`; returns `count`. `what` describes the buffer ("a 1000 × 1000
/// film").
pub fn check_with(
    what: &str,
    count: Option<u64>,
    element_bytes: u64,
    (limit, source): (u64, &str),
) -> Result<usize, TooLarge> {
    let bytes = count.map(|c| c as u128 * element_bytes as u128);
    match (count, bytes) {
        (Some(c), Some(b)) if b <= limit as u128 && usize::try_from(c).is_ok() => Ok(c as usize),
        _ => Err(TooLarge {
            what: what.to_string(),
            bytes,
            limit: format!("{}, {source}", human(limit)),
        }),
    }
}

/// Checks a buffer of `count` elements of `element_bytes` each against
/// the machine's budget.
pub fn check_buffer(what: &str, count: Option<u64>, element_bytes: u64) -> Result<usize, TooLarge> {
    check_with(what, count, element_bytes, memory_limit())
}

/// Checks a `width` × `height` image of `bytes_per_pixel` (at most
/// `MAX_PIXELS` pixels, and within the budget); returns its pixel count.
pub fn check_image(
    what: &str,
    width: u64,
    height: u64,
    bytes_per_pixel: u64,
) -> Result<usize, TooLarge> {
    let what = format!("{what} of {width} × {height} pixels");
    let count = width.checked_mul(height);
    if let Some(c) = count.filter(|&c| c > MAX_PIXELS) {
        return Err(TooLarge {
            what: format!("{what} ({c} pixels)"),
            bytes: Some(c as u128 * bytes_per_pixel as u128),
            limit: format!("2³¹ = {MAX_PIXELS} pixels per image"),
        });
    }
    check_buffer(&what, count, bytes_per_pixel)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_within_the_budget_pass_and_others_name_the_limit() {
        let budget = (1 << 20, "test budget");
        assert_eq!(check_with("x", Some(1000), 16, budget), Ok(1000));
        let e = check_with("a buffer", Some(1 << 20), 16, budget).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("a buffer would need 16.0 MiB"), "{msg}");
        assert!(
            msg.contains("the limit is 1.0 MiB (1048576 bytes), test budget"),
            "{msg}"
        );
        // A count that overflowed before it got here.
        let e = check_with("a film", None, 16, budget).unwrap_err();
        assert!(e.to_string().contains("more bytes than"), "{e}");
    }

    #[test]
    fn images_over_2_31_pixels_or_overflowing_are_errors() {
        let e = check_image("a film", 1_000_000_000, 1_000_000_000, 36).unwrap_err();
        assert!(
            e.to_string().contains("1000000000 × 1000000000 pixels"),
            "{e}"
        );
        assert!(e.to_string().contains("2³¹"), "{e}");
        let e = check_image("an EXR", u64::MAX, 3, 4).unwrap_err();
        assert!(e.bytes.is_none(), "{e}");
        assert_eq!(check_image("a film", 64, 48, 36), Ok(64 * 48));
    }

    #[test]
    fn the_budget_is_read_from_meminfo_and_the_environment_syntax() {
        let text = "MemTotal:       16384 kB\nMemFree:  1 kB\n";
        assert_eq!(mem_total(text), Some(16384 * 1024));
        assert_eq!(mem_total("nothing"), None);
        assert_eq!(parse_bytes("8G"), Some(8 << 30));
        assert_eq!(parse_bytes("1.5k"), Some(1536));
        assert_eq!(parse_bytes("100"), Some(100));
        assert_eq!(parse_bytes("-1"), None);
        assert_eq!(parse_bytes("lots"), None);
        let (limit, _) = memory_limit();
        assert!(limit > 0);
    }

    #[test]
    fn a_control_group_limit_below_the_machine_is_found_in_v1_and_v2() {
        let files = |pairs: &'static [(&'static str, &'static str)]| {
            move |p: &str| {
                pairs
                    .iter()
                    .find(|(f, _)| *f == p)
                    .map(|(_, v)| v.to_string())
            }
        };
        let v2 = files(&[("/sys/fs/cgroup/job/memory.max", "2147483648\n")]);
        assert_eq!(cgroup_limit("0::/job\n", v2), Some(2 << 30));
        let v1 = files(&[
            (
                "/sys/fs/cgroup/memory/memory.limit_in_bytes",
                "9223372036854771712",
            ),
            (
                "/sys/fs/cgroup/memory/a/b/memory.limit_in_bytes",
                "1073741824",
            ),
        ]);
        let text = "5:devices:/\n4:memory:/a/b\n0::/\n";
        assert_eq!(cgroup_limit(text, v1), Some(1 << 30));
        // No limit ("max", or v1's near-2^63) is none.
        let none = files(&[
            ("/sys/fs/cgroup/memory.max", "max"),
            (
                "/sys/fs/cgroup/memory/memory.limit_in_bytes",
                "9223372036854771712",
            ),
        ]);
        assert_eq!(cgroup_limit("0::/\n4:memory:/\n", none), None);
    }
}
