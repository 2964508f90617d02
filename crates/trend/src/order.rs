//! Putting recordings in time order: a timestamp in each file name (IMS's
//! `2004.02.12.10.32.39`, ISO-style dates such as `2024-03-01T12:00:00`,
//! `2024-03-01_12-00-00`, `20240301T120000`), plain numbers (XJTU-SY's `1.csv`, `2.csv`, …:
//! numeric, not lexicographic order), or an index CSV `file,time`.

use crate::error::{Result, TrendError};

/// What a recording's time means.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TimeAxis {
    /// Seconds since 1970-01-01T00:00:00 (the clock of the names; no time zone is read: the
    /// names' own local time, taken as UTC).
    Seconds,
    /// A recording number (XJTU-SY-style names, or a number in an index CSV): the order only.
    Index,
}

impl TimeAxis {
    /// The unit of a time on this axis, for reports.
    pub fn unit(self) -> &'static str {
        match self {
            TimeAxis::Seconds => "s since 1970-01-01T00:00:00 (names' clock)",
            TimeAxis::Index => "recording number",
        }
    }

    /// The unit a slope's denominator is in, and the factor from this axis to it (hours for
    /// [`TimeAxis::Seconds`], recordings for [`TimeAxis::Index`]).
    pub fn rate_unit(self) -> (&'static str, f64) {
        match self {
            TimeAxis::Seconds => ("h", 1.0 / 3600.0),
            TimeAxis::Index => ("recording", 1.0),
        }
    }

    /// A time on this axis as people read it (`2004-02-12T10:32:39`, or the number).
    pub fn format(self, t: f64) -> String {
        match self {
            TimeAxis::Seconds => format_seconds(t),
            TimeAxis::Index => format!("{t}"),
        }
    }
}

/// The time a file name gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NameTime {
    /// Seconds since 1970-01-01 ([`TimeAxis::Seconds`]) or the number ([`TimeAxis::Index`]).
    pub time: f64,
    /// Which.
    pub axis: TimeAxis,
}

/// Days from 1970-01-01 to a civil date (proleptic Gregorian; H. Hinnant's algorithm).
fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// The civil date of a day count from 1970-01-01 (inverse of [`days_from_civil`]).
fn civil_from_days(z: i64) -> (i64, i64, i64) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    (if m <= 2 { y + 1 } else { y }, m, d)
}

fn days_in_month(y: i64, m: i64) -> i64 {
    match m {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        _ if (y % 4 == 0 && y % 100 != 0) || y % 400 == 0 => 29,
        _ => 28,
    }
}

/// Seconds since 1970-01-01 as `YYYY-MM-DDTHH:MM:SS` (whole seconds).
pub fn format_seconds(t: f64) -> String {
    if !t.is_finite() {
        return format!("{t}");
    }
    let s = t.round() as i64;
    let (days, rem) = (s.div_euclid(86_400), s.rem_euclid(86_400));
    let (y, m, d) = civil_from_days(days);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// The calendar time in `digits` (`YYYYMMDD`, `YYYYMMDDHHMM` or `YYYYMMDDHHMMSS`), checked.
fn calendar(digits: &str) -> std::result::Result<f64, String> {
    let n = |a: usize, b: usize| digits[a..b].parse::<i64>().unwrap_or(-1);
    let (y, mo, d) = (n(0, 4), n(4, 6), n(6, 8));
    let (h, mi, s) = match digits.len() {
        8 => (0, 0, 0),
        12 => (n(8, 10), n(10, 12), 0),
        14 => (n(8, 10), n(10, 12), n(12, 14)),
        k => return Err(format!("{k} digits")),
    };
    if !(1900..=2999).contains(&y)
        || !(1..=12).contains(&mo)
        || !(1..=days_in_month(y, mo)).contains(&d)
        || !(0..=23).contains(&h)
        || !(0..=59).contains(&mi)
        || !(0..=60).contains(&s)
    {
        return Err(format!(
            "{y:04}-{mo:02}-{d:02} {h:02}:{mi:02}:{s:02} is not a calendar time"
        ));
    }
    Ok((days_from_civil(y, mo, d) * 86_400 + h * 3600 + mi * 60 + s) as f64)
}

/// The time in a file name (its stem: the name without a known recording extension `.csv`,
/// `.txt`, `.tsv`, `.mat`, `.dat`; IMS names such as `2004.02.12.10.32.39` have none).
///
/// Read as a calendar time when the name's digit groups are `YYYY MM DD [HH MM [SS]]`
/// (separated by anything: `.`, `-`, `_`, `T`, `:`, a space) or one 8/12/14-digit group,
/// possibly with an 8-digit date and a 4/6-digit time (`20240301T120000`); other text before or
/// after is allowed (`bearing1_2024-03-01T12:00:00`). A name that is only a number (`17.csv`) is
/// [`TimeAxis::Index`].
///
/// # Errors
/// [`TrendError::Timestamp`] naming the file otherwise.
pub fn parse_name(name: &str) -> Result<NameTime> {
    let base = name.rsplit(['/', '\\']).next().unwrap_or(name);
    let lower = base.to_ascii_lowercase();
    let stem = [".csv", ".txt", ".tsv", ".mat", ".dat"]
        .iter()
        .find_map(|e| lower.strip_suffix(e).map(|s| &base[..s.len()]))
        .unwrap_or(base);
    let err = |reason: String| TrendError::Timestamp {
        file: name.to_string(),
        reason,
    };
    if !stem.is_empty() && stem.bytes().all(|b| b.is_ascii_digit()) && stem.len() < 8 {
        let v: f64 = stem
            .parse::<u64>()
            .map_err(|e| err(e.to_string()))?
            .to_string()
            .parse()
            .map_err(|_| err("not a number".into()))?;
        return Ok(NameTime {
            time: v,
            axis: TimeAxis::Index,
        });
    }
    let groups: Vec<&str> = stem
        .split(|c: char| !c.is_ascii_digit())
        .filter(|g| !g.is_empty())
        .collect();
    let lens: Vec<usize> = groups.iter().map(|g| g.len()).collect();
    // the date may follow other numbered text (`bearing1_2024-03-01T12:00:00`): the first
    // suffix of the digit groups that reads as a date
    let digits: Option<String> = (0..groups.len()).find_map(|start| match &lens[start..] {
        [4, 2, 2, 2, 2, 2] | [4, 2, 2, 2, 2] | [4, 2, 2] | [8, 6] | [8, 4] | [14] | [12] | [8] => {
            Some(groups[start..].concat())
        }
        _ => None,
    });
    let Some(digits) = digits else {
        return Err(err(
            "expected YYYY.MM.DD.HH.MM.SS (IMS), an ISO date such as 2024-03-01T12:00:00 or 20240301T120000, or a number such as 1.csv".into(),
        ));
    };
    let t = calendar(&digits).map_err(err)?;
    Ok(NameTime {
        time: t,
        axis: TimeAxis::Seconds,
    })
}

/// A time as written in an index CSV: a number (a position on a [`TimeAxis::Index`] axis: its
/// order and spacing are used, slopes are per unit of it) or a calendar time as [`parse_name`]
/// reads it ([`TimeAxis::Seconds`]).
///
/// # Errors
/// [`TrendError::Timestamp`] when it is neither.
pub fn parse_time(text: &str) -> Result<NameTime> {
    let t = text.trim();
    let date_like = matches!(t.len(), 8 | 12 | 14)
        && t.bytes().all(|b| b.is_ascii_digit())
        && parse_name(t).is_ok();
    if let Ok(v) = t.parse::<f64>()
        && v.is_finite()
        && !date_like
    {
        return Ok(NameTime {
            time: v,
            axis: TimeAxis::Index,
        });
    }
    parse_name(t)
}

/// Order `names` (file names or paths) by the times their names give: the permutation that
/// sorts them, with each one's time, and the axis they share.
///
/// # Errors
/// An unreadable name ([`TrendError::Timestamp`]), names mixing timestamps and numbers
/// ([`TrendError::MixedNaming`]), two names with the same time ([`TrendError::DuplicateTime`]);
/// each naming the file.
pub fn order_names<S: AsRef<str>>(names: &[S]) -> Result<(Vec<(usize, f64)>, TimeAxis)> {
    let times: Vec<(usize, NameTime)> = names
        .iter()
        .enumerate()
        .map(|(i, n)| parse_name(n.as_ref()).map(|t| (i, t)))
        .collect::<Result<_>>()?;
    order_times(names, &times)
}

/// Order entries with times given (`times[k] = (index into names, time)`), checking one axis and
/// no duplicates.
///
/// # Errors
/// As [`order_names`].
pub fn order_times<S: AsRef<str>>(
    names: &[S],
    times: &[(usize, NameTime)],
) -> Result<(Vec<(usize, f64)>, TimeAxis)> {
    let axis_name = |a: TimeAxis| match a {
        TimeAxis::Seconds => "by a timestamp",
        TimeAxis::Index => "by a number",
    };
    let Some(&(first, t0)) = times.first() else {
        return Ok((Vec::new(), TimeAxis::Index));
    };
    for &(i, t) in times {
        if t.axis != t0.axis {
            return Err(TrendError::MixedNaming {
                file: names[i].as_ref().to_string(),
                found: axis_name(t.axis),
                first: names[first].as_ref().to_string(),
                expected: axis_name(t0.axis),
            });
        }
    }
    let mut order: Vec<(usize, f64)> = times.iter().map(|&(i, t)| (i, t.time)).collect();
    order.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    for w in order.windows(2) {
        if w[0].1 == w[1].1 {
            let (a, b) = (w[0].0.min(w[1].0), w[0].0.max(w[1].0));
            return Err(TrendError::DuplicateTime {
                file: names[b].as_ref().to_string(),
                other: names[a].as_ref().to_string(),
                time: t0.axis.format(w[0].1),
            });
        }
    }
    Ok((order, t0.axis))
}

/// One row of an index CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct IndexEntry {
    /// The file as written in the index.
    pub file: String,
    /// Its time.
    pub time: NameTime,
    /// 1-based line in the index.
    pub line: usize,
    /// Optional `start_s` column: the recording starts this many seconds into the file.
    pub start_s: Option<f64>,
    /// Optional `duration_s` column: only this many seconds are read (so one long file can give
    /// several recordings of a staged sequence).
    pub duration_s: Option<f64>,
}

/// Parse an index CSV (`path` names it in errors): a header `file,time` (either order, case
/// ignored; optional `start_s` and `duration_s` columns cut a segment of the file, seconds;
/// further columns ignored), then one row per recording; blank lines and `#` comments
/// skipped. Times are numbers or calendar times ([`parse_time`]), one kind for the whole file.
///
/// # Errors
/// [`TrendError::IndexCsv`] for a missing header or field, a bad time (the line named), mixed
/// time kinds; no rows.
pub fn parse_index(path: &str, text: &str) -> Result<Vec<IndexEntry>> {
    let err = |line: usize, reason: String| TrendError::IndexCsv {
        path: path.to_string(),
        line,
        reason,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_start_matches('\u{feff}').trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (hl, header) = lines
        .next()
        .ok_or_else(|| err(1, "empty index (expected a header `file,time`)".into()))?;
    let cols: Vec<String> = header
        .split(',')
        .map(|c| c.trim().trim_matches('"').to_ascii_lowercase())
        .collect();
    let (fc, tc) = match (
        cols.iter().position(|c| c == "file"),
        cols.iter().position(|c| c == "time"),
    ) {
        (Some(f), Some(t)) => (f, t),
        _ => {
            return Err(err(
                hl,
                format!("header `{header}`: expected columns `file` and `time`"),
            ));
        }
    };
    let mut out = Vec::new();
    for (line, l) in lines {
        let f: Vec<&str> = l.split(',').map(|c| c.trim().trim_matches('"')).collect();
        let (Some(file), Some(time)) = (f.get(fc), f.get(tc)) else {
            return Err(err(line, format!("`{l}` has no `file` or `time` field")));
        };
        if file.is_empty() {
            return Err(err(line, "empty `file`".into()));
        }
        let seconds = |name: &str| -> Result<Option<f64>> {
            let Some(c) = cols.iter().position(|c| c == name) else {
                return Ok(None);
            };
            match f.get(c).copied().filter(|v| !v.is_empty()) {
                None => Ok(None),
                Some(v) => match v.parse::<f64>() {
                    Ok(x) if x.is_finite() && x >= 0.0 => Ok(Some(x)),
                    _ => Err(err(
                        line,
                        format!("{file}: `{name}` = {v:?} is not a number of seconds >= 0"),
                    )),
                },
            }
        };
        let (start_s, duration_s) = (seconds("start_s")?, seconds("duration_s")?);
        if duration_s == Some(0.0) {
            return Err(err(line, format!("{file}: `duration_s` is 0")));
        }
        let t = parse_time(time).map_err(|e| err(line, format!("{file}: {e}")))?;
        if let Some(first) = out.first().map(|e: &IndexEntry| e.time.axis)
            && first != t.axis
        {
            return Err(err(
                line,
                format!(
                    "{file}: time `{time}` is of another kind than the first row's (all numbers or all calendar times)"
                ),
            ));
        }
        out.push(IndexEntry {
            file: file.to_string(),
            time: t,
            line,
            start_s,
            duration_s,
        });
    }
    if out.is_empty() {
        return Err(err(hl, "no rows after the header".into()));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ims_and_iso_names() {
        let a = parse_name("2004.02.12.10.32.39").unwrap();
        assert_eq!(a.axis, TimeAxis::Seconds);
        assert_eq!(format_seconds(a.time), "2004-02-12T10:32:39");
        for n in [
            "2024-03-01T12:00:00",
            "2024-03-01_12-00-00.csv",
            "20240301T120000",
            "pump_20240301_120000.txt",
            "2024-03-01 12:00:00",
            "bearing1_2024-03-01T12:00:00.csv",
        ] {
            let t = parse_name(n).unwrap_or_else(|e| panic!("{n}: {e}"));
            assert_eq!(format_seconds(t.time), "2024-03-01T12:00:00", "{n}");
        }
        assert_eq!(
            parse_name("2024-03-01T12:00:10").unwrap().time
                - parse_name("2024-03-01T12:00:00").unwrap().time,
            10.0
        );
    }

    #[test]
    fn numbers_in_numeric_order() {
        let names = ["10.csv", "2.csv", "1.csv"];
        let (o, axis) = order_names(&names).unwrap();
        assert_eq!(axis, TimeAxis::Index);
        assert_eq!(o.iter().map(|p| p.0).collect::<Vec<_>>(), vec![2, 1, 0]);
    }

    #[test]
    fn bad_names_are_typed_errors_naming_the_file() {
        let e = parse_name("notes.csv").unwrap_err().to_string();
        assert!(e.starts_with("notes.csv:"), "{e}");
        let e = parse_name("2004.02.30.10.32.39").unwrap_err().to_string();
        assert!(e.contains("not a calendar time"), "{e}");
        let e = order_names(&["2004.02.12.10.32.39", "dir/2004.02.12.10.32.39"])
            .unwrap_err()
            .to_string();
        assert!(e.contains("duplicate") && e.contains("dir/2004"), "{e}");
        let e = order_names(&["1.csv", "2004.02.12.10.32.39"])
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("2004.02.12.10.32.39:"), "{e}");
    }

    #[test]
    fn index_csv() {
        let rows = parse_index("i.csv", "file,time\n/a/97.mat,0\nb/105.mat,1\n").unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[1].file, "b/105.mat");
        assert_eq!(rows[1].time.axis, TimeAxis::Index);
        let rows = parse_index("i.csv", "time,file\n2024-03-01T12:00:00,x.csv\n").unwrap();
        assert_eq!(rows[0].time.axis, TimeAxis::Seconds);
        let e = parse_index("i.csv", "file,time\nx,0\ny,2024-03-01T12:00:00\n").unwrap_err();
        assert!(e.to_string().contains("line 3"), "{e}");
        assert!(parse_index("i.csv", "name,t\n").is_err());
        let rows = parse_index(
            "i.csv",
            "file,time,start_s,duration_s\n97.mat,0,0,2\n97.mat,1,2,2\n",
        )
        .unwrap();
        assert_eq!(
            (rows[1].start_s, rows[1].duration_s),
            (Some(2.0), Some(2.0))
        );
        assert!(parse_index("i.csv", "file,time,start_s\n97.mat,0,-1\n").is_err());
    }

    #[test]
    fn calendar_round_trip() {
        for s in [0_i64, 951_782_400, 1_077_000_000, 4_102_444_799] {
            let f = format_seconds(s as f64);
            let back = parse_name(&f).unwrap().time;
            assert_eq!(back, s as f64, "{f}");
        }
    }

    proptest::proptest! {
        /// The ordering is a permutation of the input, sorted by time.
        #[test]
        fn ordering_is_a_sorted_permutation(nums in proptest::collection::hash_set(0u32..100_000, 1..40)) {
            let names: Vec<String> = nums.iter().map(|n| format!("{n}.csv")).collect();
            let (o, _) = order_names(&names).unwrap();
            let mut idx: Vec<usize> = o.iter().map(|p| p.0).collect();
            idx.sort_unstable();
            proptest::prop_assert_eq!(idx, (0..names.len()).collect::<Vec<_>>());
            proptest::prop_assert!(o.windows(2).all(|w| w[0].1 < w[1].1));
        }
    }
}
