//! `hybrid-fdd simulate` (and `cargo xtask simulate`): simulate a recording and write it as CSV:
//! one header row, `time_s,accel`, plus all ten states with `--states` (5-DOF sets only). A JSON
//! sidecar (`<out>.json`) records every parameter used, the declared speed (`rpm`, which
//! `diagnose` and `close-loop` take when `--rpm` is omitted), the bearing (`bearing`, which
//! `close-loop` and `calibrate` take when `--bearing` is omitted) and the unit of `accel`
//! (`accel_unit`).
//!
//! At CWRU conditions (6205, 12 kHz) the default is the **calibrated rig**
//! (`calibrated_rig::cwru_rig`, made by `cargo xtask calibrate-rig`): the 5-DOF model behind the
//! measured paths of the CWRU rig, in g like the CWRU data. `--params cwru` (the physically
//! consistent, uncalibrated 5-DOF set) and `--params table2.1` (the dissertation's) give the bare
//! 5-DOF housing acceleration in m/s².

use anyhow::Context as _;
use bearing_model::{
    Bearing, FaultClass, FaultSet, Noise, ParamSet, Scenario, SimConfig, Slip, Spall,
    scenario::CWRU_DEPTH_M,
};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::flags::FaultClassParser;

/// Flags of this task.
#[derive(clap::Args, Debug)]
// a negative --rpm or --fs gets the range error, not "unexpected argument"
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Fault class: none (also normal, healthy), inner, outer, ball or a combination joined by
    /// `+` (also `-` or `,`; `ir`, `or`, `b` for short; any order and case).
    #[arg(long, default_value = "none", value_parser = FaultClassParser)]
    pub fault: FaultClass,
    /// Shaft speed, rpm (> 0).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1797.0)]
    pub rpm: f64,
    /// Output sampling rate, Hz.
    #[arg(long, allow_negative_numbers = true, default_value_t = 12_000.0)]
    pub fs: f64,
    /// Duration, s.
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0)]
    pub duration: f64,
    /// Seed of slip, parameter uncertainty and noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Parameter set: auto (the calibrated CWRU rig for the 6205 at 12 kHz, else cwru) |
    /// calibrated | cwru (physically consistent, uncalibrated 5-DOF set) | table2.1
    /// (dissertation, as printed).
    #[arg(long, default_value = "auto")]
    pub params: String,
    /// Outer-race spall position, o'clock: 6 (load zone), 3, 9 or 12 (CWRU's positions are
    /// 3, 6 and 12).
    #[arg(long, default_value_t = 6)]
    pub outer_clock: u8,
    /// Bearing: 6205 (CWRU drive end) | 6203 (fan end) | another designation from the built-in
    /// catalogue (`hybrid-fdd bearings` lists them; case-insensitive: `uc204`, `6308`) | a
    /// geometry `n=8,d=0.235in,D=1.245in,angle=0deg` (mm, in or m). The calibrated rig is
    /// `--bearing 6205`'s; any other runs on the bare 5-DOF sets only: the set's shaft, pedestal,
    /// housing and contact stiffness with this bearing's balls and kinematics.
    #[arg(long, default_value = "6205")]
    pub bearing: String,
    /// Spall width (circumferential), mm. CWRU: 0.178 / 0.356 / 0.533 (0.007/0.014/0.021 in).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.1778)]
    pub fault_size: f64,
    /// Spall depth, mm (CWRU EDM depth 0.011 in = 0.2794 mm).
    #[arg(long, allow_negative_numbers = true, default_value_t = CWRU_DEPTH_M * 1e3)]
    pub fault_depth: f64,
    /// Random ball slip as a fraction of the ball spacing (0 = off).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.01)]
    pub slip: f64,
    /// Measurement noise as SNR in dB (omit for no noise).
    #[arg(long, allow_negative_numbers = true)]
    pub snr_db: Option<f64>,
    /// Constant radial load on the shaft, N (down).
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.0)]
    pub radial_load: f64,
    /// Housing resonance, Hz (default: the parameter set's, 3300 Hz).
    #[arg(long, allow_negative_numbers = true)]
    pub resonance: Option<f64>,
    /// Fault onset time T_f, s: in [0, --duration) (default: present from the start).
    #[arg(long, allow_negative_numbers = true)]
    pub onset: Option<f64>,
    /// Largest internal RK4 step, s.
    #[arg(long, allow_negative_numbers = true, default_value_t = SimConfig::DEFAULT_MAX_STEP)]
    pub max_step: f64,
    /// Also write all ten states (m, m/s) as columns.
    #[arg(long)]
    pub states: bool,
    /// Output CSV path.
    #[arg(long)]
    pub out: PathBuf,
}

const STATE_NAMES: [&str; 10] = [
    "xs_m", "ys_m", "xp_m", "yp_m", "yr_m", "vxs_m_s", "vys_m_s", "vxp_m_s", "vyp_m_s", "vyr_m_s",
];

/// Build the scenario the flags describe (all validation errors are `bearing-model`'s).
pub fn scenario(args: &Args) -> anyhow::Result<Scenario> {
    let class = args.fault;
    let set: ParamSet = match args.params.to_ascii_lowercase().as_str() {
        "auto" | "calibrated" => ParamSet::CwruRig,
        other => other.parse()?,
    };
    let geometry = simulated_geometry(&args.bearing)?;
    check_rpm(args.rpm)?;
    anyhow::ensure!(
        args.slip.is_finite() && args.slip >= 0.0,
        "--slip must be >= 0 (got {})",
        args.slip
    );
    let mut sc = Scenario::new(set, Bearing::Skf6205, args.rpm);
    sc.spec.geometry = geometry;
    let mut sc = sc
        .with_fs(args.fs)
        .with_duration(args.duration)
        .with_seed(args.seed)
        .with_radial_load(args.radial_load)
        .with_states(args.states)
        .with_slip(if args.slip > 0.0 {
            Slip::Random {
                fraction: args.slip,
            }
        } else {
            Slip::Off
        })
        .with_noise(args.snr_db.map_or(Noise::Off, Noise::SnrDb));
    sc.sim.max_step_s = args.max_step;
    if class != FaultClass::None {
        sc.spec.faults = FaultSet::of_class(
            class,
            Spall::new(args.fault_size * 1e-3).with_depth(args.fault_depth * 1e-3),
        );
        if let Some(o) = sc.spec.faults.outer.as_mut() {
            o.angle_rad = outer_angle(args.outer_clock)?;
        }
    }
    if let Some(f) = args.resonance {
        sc.spec.housing.resonance_hz = f;
    }
    if let Some(t) = args.onset {
        // checked here too, so an onset is refused even with --fault none
        bearing_model::fault::check_onset(t, args.duration)?;
        sc = sc.with_fault_onset(t);
    }
    Ok(sc)
}

/// The geometry the bare 5-DOF model simulates for `--bearing`: a built-in bearing's, or one
/// given as `n=…,d=…,D=…[,angle=…]` (the four fault multiples alone do not place balls).
///
/// # Errors
/// The spec parser's typed errors, and a spec without a geometry.
pub fn simulated_geometry(spec: &str) -> anyhow::Result<bearing_model::BearingGeometry> {
    // the parser names a built-in bearing by its geometry too
    crate::parse_bearing(spec)?.geometry.ok_or_else(|| {
        anyhow::anyhow!(
            "--bearing {}: simulating needs the bearing's geometry (n=…,d=…,D=…[,angle=…]), not only its fault multiples",
            spec.trim()
        )
    })
}

fn check_rpm(rpm: f64) -> anyhow::Result<()> {
    anyhow::ensure!(
        rpm.is_finite() && rpm > 0.0,
        "--rpm must be > 0 (got {rpm})"
    );
    Ok(())
}

/// Spall angle of an o'clock position (y up: 6 o'clock = −π/2, 3 o'clock = 0, 12 = π/2).
fn outer_angle(clock: u8) -> anyhow::Result<f64> {
    Ok(match clock {
        6 => -std::f64::consts::FRAC_PI_2,
        3 => 0.0,
        12 => std::f64::consts::FRAC_PI_2,
        9 => std::f64::consts::PI,
        other => anyhow::bail!("--outer-clock must be 3, 6, 9 or 12 (got {other})"),
    })
}

/// Whether the flags ask for the calibrated rig: `calibrated`, or `auto` at its conditions.
///
/// # Errors
/// `--params calibrated` away from the rig's conditions (bearing, sampling rate).
pub fn wants_rig(args: &Args, rig: &calibrated_rig::RigModel) -> anyhow::Result<bool> {
    let p = args.params.to_ascii_lowercase();
    let at = rig.check_compatible(args.fs, args.bearing.trim()).is_ok();
    match p.as_str() {
        "calibrated" if !at => anyhow::bail!(
            "the calibrated rig is the {} at {} Hz; got --bearing {} --fs {} (use --params cwru)",
            rig.bearing,
            rig.fs_hz,
            args.bearing,
            args.fs
        ),
        "calibrated" => Ok(true),
        "auto" => Ok(at),
        _ => Ok(false),
    }
}

/// Flags that only the bare 5-DOF sets use, set away from their defaults.
fn bare_only_flags(args: &Args) -> Vec<&'static str> {
    let mut v = Vec::new();
    // a NaN differs from every default (and is refused where the flag applies)
    let d = |a: f64, b: f64| a.is_nan() || (a - b).abs() > 1e-12;
    if args.states {
        v.push("--states");
    }
    if args.snr_db.is_some() {
        v.push("--snr-db");
    }
    if d(args.radial_load, 0.0) {
        v.push("--radial-load");
    }
    if args.resonance.is_some() {
        v.push("--resonance");
    }
    if args.onset.is_some() {
        v.push("--onset");
    }
    if d(args.max_step, SimConfig::DEFAULT_MAX_STEP) {
        v.push("--max-step");
    }
    if d(args.fault_depth, CWRU_DEPTH_M * 1e3) {
        v.push("--fault-depth");
    }
    if d(args.slip, 0.01) {
        v.push("--slip");
    }
    v
}

/// Simulate with the calibrated rig: the recording (g) and its sidecar's `rig` object.
///
/// # Errors
/// Flags the rig does not take, and the rig's typed errors.
pub fn simulate_rig(
    args: &Args,
    rig: &calibrated_rig::RigModel,
) -> anyhow::Result<(Vec<f64>, serde_json::Value)> {
    let bare = bare_only_flags(args);
    anyhow::ensure!(
        bare.is_empty(),
        "{} only {} to the bare 5-DOF sets (--params cwru|table2.1), not to the calibrated rig",
        bare.join(", "),
        if bare.len() == 1 { "applies" } else { "apply" }
    );
    let class = args.fault;
    check_rpm(args.rpm)?;
    anyhow::ensure!(
        args.duration.is_finite() && args.duration > 0.0 && args.duration <= 3600.0,
        "--duration must be in (0, 3600] s (got {})",
        args.duration
    );
    let n = (args.duration * args.fs).round() as usize;
    anyhow::ensure!(
        n >= 1024,
        "--duration {} s is {n} samples at {} Hz; the calibrated rig needs at least 1024 (--duration {:.3} s or more)",
        args.duration,
        args.fs,
        1024.0 / args.fs
    );
    let mut syn = calibrated_rig::Synthesis::new(class, args.fault_size, args.rpm, n, args.seed);
    syn.outer_angle_rad = outer_angle(args.outer_clock)?;
    let y = rig
        .synthesize(&syn)
        .context("the calibrated rig cannot simulate this")?;
    let mut used = serde_json::Map::new();
    for loc in calibrated_rig::Location::ALL
        .into_iter()
        .filter(|l| l.in_class(class))
    {
        let (g, q) = rig.severity_at(loc, args.fault_size, syn.outer_angle_rad)?;
        let strike = rig.strike_fraction_at(loc, args.fault_size, syn.outer_angle_rad)?;
        // severity_at() above has already failed for a location without any calibrated size
        let ((lo, hi), at_position) = rig
            .calibrated_range_mm_at(loc, syn.outer_angle_rad)
            .unwrap_or(((args.fault_size, args.fault_size), false));
        let extrapolated =
            args.fault_size < lo * (1.0 - 1e-9) || args.fault_size > hi * (1.0 + 1e-9);
        used.insert(
            loc.name().into(),
            serde_json::json!({
                "gain": g,
                "random_fraction": q,
                "strike_fraction": strike,
                "calibrated_range_mm": [lo, hi],
                "extrapolated": extrapolated,
                "own_position_severity": at_position,
            }),
        );
    }
    let info = serde_json::json!({
        "format": rig.format,
        "version": rig.version,
        "units": rig.units,
        "provenance": rig.provenance,
        "preload_m": rig.preload_m,
        "radial_load_n": rig.radial_load_n,
        "sensor_horizontal": rig.sensor_horizontal,
        "speed_ratio": rig.healthy.speed_ratio,
        "severity_used": used,
        "calibrated_sizes_mm": rig.severities.iter().map(|s| (s.location.name(), s.size_mm)).collect::<Vec<_>>(),
    });
    Ok((y, info))
}

/// Write a recording as CSV: header `time_s,accel[,states…]`, one row per sample.
pub fn write_csv(path: &Path, rec: &bearing_model::SimulatedRecording) -> anyhow::Result<()> {
    let f = std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = std::io::BufWriter::new(f);
    write!(w, "time_s,accel")?;
    if rec.states.is_some() {
        for n in STATE_NAMES {
            write!(w, ",{n}")?;
        }
    }
    writeln!(w)?;
    for (k, a) in rec.accel.iter().enumerate() {
        write!(w, "{:.9},{:e}", rec.time(k), a)?;
        if let Some(st) = &rec.states {
            for v in st[k].iter() {
                write!(w, ",{v:e}")?;
            }
        }
        writeln!(w)?;
    }
    w.flush()?;
    Ok(())
}

/// Notes on stderr for what the simulation cannot stand for: fault rates at or above Nyquist (no
/// envelope line can show them) and, on the calibrated rig, spall sizes outside the calibrated
/// ones (the nearest calibrated severity is held).
fn warn_limits(
    args: &Args,
    class: FaultClass,
    orders: &bearing_model::FaultOrders,
    shaft_hz: f64,
    rig_info: Option<&serde_json::Value>,
) {
    for loc in calibrated_rig::Location::ALL
        .into_iter()
        .filter(|l| l.in_class(class))
    {
        let rate = shaft_hz * orders.of(loc);
        if rate >= 0.5 * args.fs {
            eprintln!(
                "note: the {} fault rate, {rate:.1} Hz, is at or above Nyquist ({:.0} Hz): its lines cannot be seen in this recording",
                loc.name(),
                0.5 * args.fs
            );
        }
        let used = rig_info.and_then(|i| i["severity_used"].get(loc.name()));
        if let Some(u) = used.filter(|u| u["extrapolated"] == true) {
            let r = &u["calibrated_range_mm"];
            eprintln!(
                "note: a {} mm {} spall is outside the calibrated sizes ({:.3}–{:.3} mm): the nearest calibrated severity is held, so its level and impulsiveness are not calibrated",
                args.fault_size,
                loc.name(),
                r[0].as_f64().unwrap_or(f64::NAN),
                r[1].as_f64().unwrap_or(f64::NAN)
            );
        }
    }
}

/// Run the task.
pub fn run(args: Args) -> anyhow::Result<()> {
    let is_json = args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    anyhow::ensure!(
        !is_json,
        "--out {} would be overwritten by its own JSON sidecar (written beside the CSV with the extension .json): name the recording .csv",
        args.out.display()
    );
    let rig = calibrated_rig::cwru_rig().context("loading the calibrated CWRU rig")?;
    if wants_rig(&args, &rig)? {
        return run_rig(&args, &rig);
    }
    if args.params.eq_ignore_ascii_case("auto") {
        crate::say!(
            "note: the bare 5-DOF model (m/s^2): the calibrated rig exists for the {} at {} Hz only",
            rig.bearing,
            rig.fs_hz
        );
    }
    let sc = scenario(&args)?;
    let model = sc.model().context("invalid model parameters")?;
    let t = std::time::Instant::now();
    let rec = bearing_model::simulate(&model, &sc.sim).context("simulation failed")?;
    let wall = t.elapsed().as_secs_f64();
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    write_csv(&args.out, &rec)?;
    let meta = serde_json::json!({
        "generator": "hybrid-fdd simulate / cargo xtask simulate (bearing-model)",
        "rpm": args.rpm,
        "bearing": args.bearing.trim(),
        "columns": { "time_s": "s", "accel": "housing (sprung-mass) acceleration, m/s^2" },
        "accel_unit": "m/s^2",
        "fs_hz": rec.fs_hz,
        "samples": rec.accel.len(),
        "step_s": rec.step_s,
        "noise_std_m_s2": rec.noise_std,
        "fault": args.fault.name(),
        "params": args.params,
        "seed": args.seed,
        "duration_s": args.duration,
        "fault_orders": sc.spec.geometry.orders(),
        "shaft_hz": sc.spec.speed.hz(),
        "spec": sc.spec,
        "sim": sc.sim,
    });
    let side = args.out.with_extension("json");
    std::fs::write(&side, serde_json::to_string_pretty(&meta)?)
        .with_context(|| format!("writing {}", side.display()))?;
    warn_limits(
        &args,
        args.fault,
        &sc.spec.geometry.orders(),
        sc.spec.speed.hz(),
        None,
    );
    let o = sc.spec.geometry.orders().at(sc.spec.speed.hz());
    crate::say!(
        "wrote {} ({} samples at {} Hz, accel in m/s^2; step {:.3e} s; {:.1} simulated s per wall s)",
        args.out.display(),
        rec.accel.len(),
        rec.fs_hz,
        rec.step_s,
        (sc.sim.duration_s + sc.sim.settle_s) / wall.max(1e-9)
    );
    print_lines(sc.spec.speed.hz(), &o, &side);
    Ok(())
}

/// The kinematic lines of the simulated speed and where the metadata went.
fn print_lines(fr: f64, o: &bearing_model::FaultOrders, side: &Path) {
    crate::say!(
        "lines: fr {fr:.2} Hz, FTF {:.2}, BPFO {:.2}, BPFI {:.2}, ball defect (2xBSF) {:.2} Hz; metadata {}",
        o.ftf,
        o.bpfo,
        o.bpfi,
        o.ball_defect,
        side.display()
    );
}

/// The calibrated rig's branch of [`run`].
fn run_rig(args: &Args, rig: &calibrated_rig::RigModel) -> anyhow::Result<()> {
    let t = std::time::Instant::now();
    let (y, info) = simulate_rig(args, rig)?;
    let wall = t.elapsed().as_secs_f64();
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let rec = bearing_model::SimulatedRecording {
        fs_hz: args.fs,
        accel: y,
        states: None,
        step_s: f64::NAN,
        steps: 0,
        noise_std: 0.0,
    };
    write_csv(&args.out, &rec)?;
    let geometry = args.bearing.parse::<Bearing>()?.geometry();
    let shaft_hz = args.rpm / 60.0 * rig.healthy.speed_ratio;
    let meta = serde_json::json!({
        "generator": "hybrid-fdd simulate / cargo xtask simulate (calibrated CWRU rig, calibrated_rig)",
        "rpm": args.rpm,
        "bearing": args.bearing.trim(),
        "columns": { "time_s": "s", "accel": format!("acceleration at the drive-end sensor, {} (calibrated CWRU rig; the CWRU data read as g)", rig.units) },
        "accel_unit": rig.units,
        "fs_hz": args.fs,
        "samples": rec.accel.len(),
        "step_s": null,
        "noise_std_m_s2": null,
        "fault": args.fault.name(),
        "fault_size_mm": args.fault_size,
        "outer_clock": args.outer_clock,
        "params": "calibrated",
        "seed": args.seed,
        "duration_s": args.duration,
        "fault_orders": geometry.orders(),
        "shaft_hz": shaft_hz,
        "spec": null,
        "sim": null,
        "rig": info,
    });
    let side = args.out.with_extension("json");
    std::fs::write(&side, serde_json::to_string_pretty(&meta)?)
        .with_context(|| format!("writing {}", side.display()))?;
    crate::say!(
        "wrote {} ({} samples at {} Hz, accel in {}; calibrated CWRU rig; {:.1} simulated s per wall s)",
        args.out.display(),
        rec.accel.len(),
        args.fs,
        rig.units,
        args.duration / wall.max(1e-9)
    );
    warn_limits(
        args,
        args.fault,
        &geometry.orders(),
        shaft_hz,
        meta.get("rig"),
    );
    let o = geometry.orders().at(shaft_hz);
    print_lines(shaft_hz, &o, &side);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(clap::Parser)]
    struct Cli {
        #[command(flatten)]
        a: Args,
    }

    fn parse(extra: &[&str]) -> Args {
        let mut v = vec!["simulate"];
        v.extend_from_slice(extra);
        Cli::parse_from(v).a
    }

    #[test]
    fn csv_round_trips_through_the_data_crate() {
        let dir = std::env::temp_dir().join(format!("xtask-sim-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("rec.csv");
        let args = parse(&[
            "--fault",
            "inner+outer",
            "--duration",
            "0.05",
            "--seed",
            "3",
            "--states",
            "--out",
            out.to_str().unwrap(),
        ]);
        let sc = scenario(&args).unwrap();
        let rec = sc.simulate().unwrap();
        write_csv(&out, &rec).unwrap();
        let sig = bearing_data::read_csv_file(
            &out,
            &bearing_data::CsvOptions::new(rec.fs_hz, bearing_data::Column::Name("accel".into())),
        )
        .unwrap();
        assert_eq!(sig.samples().len(), rec.accel.len());
        for (a, b) in sig.samples().iter().zip(&rec.accel) {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-30));
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn the_calibrated_rig_is_the_default_at_cwru_conditions() {
        let rig = calibrated_rig::cwru_rig().unwrap();
        let args = parse(&[
            "--fault",
            "outer",
            "--duration",
            "0.5",
            "--out",
            "/tmp/x.csv",
        ]);
        assert!(wants_rig(&args, &rig).unwrap());
        let (y, info) = simulate_rig(&args, &rig).unwrap();
        assert_eq!(y.len(), 6000);
        let used = &info["severity_used"]["outer"];
        assert!(used["gain"].as_f64().unwrap() > 0.0);
        let p = used["strike_fraction"].as_f64().unwrap();
        assert!(p > 0.0 && p <= 1.0);
        assert_eq!(used["extrapolated"], false);
        // a spall wider than every calibrated one holds the nearest severity and says so
        let wide = parse(&[
            "--fault",
            "inner",
            "--fault-size",
            "3",
            "--duration",
            "0.5",
            "--out",
            "/tmp/x.csv",
        ]);
        let (_, info) = simulate_rig(&wide, &rig).unwrap();
        assert_eq!(info["severity_used"]["inner"]["extrapolated"], true);
        // the recording may not take its own sidecar's name
        let clash = parse(&[
            "--fault",
            "inner",
            "--duration",
            "0.5",
            "--out",
            "/tmp/x.JSON",
        ]);
        assert!(run(clash).is_err());
        // other conditions or explicit sets: the bare 5-DOF model
        let bare = parse(&["--fs", "48000", "--out", "/tmp/x.csv"]);
        assert!(!wants_rig(&bare, &rig).unwrap());
        let bare = parse(&["--params", "cwru", "--out", "/tmp/x.csv"]);
        assert!(!wants_rig(&bare, &rig).unwrap());
        // the rig asked for away from its conditions, or with a bare-model flag: errors
        let bad = parse(&[
            "--params",
            "calibrated",
            "--fs",
            "48000",
            "--out",
            "/tmp/x.csv",
        ]);
        assert!(wants_rig(&bad, &rig).is_err());
        let bad = parse(&["--snr-db", "20", "--out", "/tmp/x.csv"]);
        assert!(simulate_rig(&bad, &rig).is_err());
        let bad = parse(&[
            "--outer-clock",
            "5",
            "--fault",
            "outer",
            "--out",
            "/tmp/x.csv",
        ]);
        assert!(simulate_rig(&bad, &rig).is_err());
    }

    #[test]
    fn bad_flags_are_errors() {
        let bad = |extra: &[&str]| {
            let mut v = extra.to_vec();
            v.extend_from_slice(&["--out", "/nonexistent/x.csv"]);
            let a = parse(&v);
            scenario(&a).and_then(|s| Ok(s.model()?)).and_then(|_| {
                let s = scenario(&a)?;
                Ok(s.simulate()?)
            })
        };
        assert!(bad(&["--rpm", "0"]).is_err());
        assert!(bad(&["--fault", "outer", "--fault-size", "-1"]).is_err());
        assert!(bad(&["--fault", "inner", "--fault-size", "20"]).is_err());
        assert!(bad(&["--fs", "2000"]).is_err());
        assert!(bad(&["--params", "foo"]).is_err());
        // an unknown fault is refused as the flag is read
        let unknown = Cli::try_parse_from(["simulate", "--fault", "cage", "--out", "x.csv"]);
        assert!(unknown.is_err_and(|e| e.kind() == clap::error::ErrorKind::InvalidValue));
    }
}
