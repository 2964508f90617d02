//! MAT files shaped like other rigs' (MFPT's struct `bearing`, Paderborn's struct array
//! `X.Y(k)` with `Name`/`Data`, plain top-level variables, cells), written in memory by
//! `bearing_data::write_mat` from a deterministic signal.

use bearing_data::{MatArray, write_mat};

/// The signal every fixture holds: 2048 samples of a sine rounded to 1e-3.
pub fn expected_signal() -> Vec<f64> {
    (0..2048)
        .map(|n| ((2.0 * std::f64::consts::PI * 0.01 * n as f64).sin() * 1000.0).round() / 1000.0)
        .collect()
}

fn column(x: &[f64]) -> MatArray {
    MatArray::Double(vec![x.len(), 1], x.to_vec())
}

fn row(x: &[f64]) -> MatArray {
    MatArray::Double(vec![1, x.len()], x.to_vec())
}

fn scalar(v: f64) -> MatArray {
    MatArray::Double(vec![1, 1], vec![v])
}

fn text(s: &str) -> MatArray {
    MatArray::Text(s.into())
}

/// Paderborn's shape: `Info` text and a 1×3 struct array `Y` of `Name`, `Type`, `Data`, the
/// vibration `vib` as the second element's data.
fn paderborn(vib: &[f64]) -> MatArray {
    let elem = |name: &str, data: &[f64]| vec![text(name), text("Mechanic"), row(data)];
    let fields = |f: &[&str]| f.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    MatArray::Struct(
        fields(&["Info", "Y"]),
        vec![vec![
            text("N15_M07_F10"),
            MatArray::Struct(
                fields(&["Name", "Type", "Data"]),
                vec![
                    elem("force", &(0..16).map(f64::from).collect::<Vec<_>>()),
                    elem("vibration_1", vib),
                    elem("speed", &[1500.0; 16]),
                ],
            ),
        ]],
    )
}

/// The bytes of the fixture `name`.
pub fn fixture(name: &str) -> Vec<u8> {
    let sig = expected_signal();
    match name {
        "mfpt_like.mat" => write_mat(
            &[(
                "bearing",
                MatArray::Struct(
                    ["gs", "sr", "load", "rate"].map(String::from).to_vec(),
                    vec![vec![
                        column(&sig),
                        scalar(48828.0),
                        scalar(270.0),
                        scalar(25.0),
                    ]],
                ),
            )],
            true,
        ),
        "paderborn_like.mat" => write_mat(&[("N15_M07_F10_KA01_1", paderborn(&sig))], true),
        // the same tree uncompressed and small, for the mutation tests
        "struct_v5.mat" => write_mat(&[("X", paderborn(&sig[..64]))], false),
        "plain.mat" => write_mat(
            &[
                (
                    "vib",
                    MatArray::Single(vec![sig.len(), 1], sig.iter().map(|&v| v as f32).collect()),
                ),
                ("fs", scalar(25600.0)),
                ("unit", text("g")),
                (
                    "counts",
                    MatArray::Int16(
                        vec![sig.len(), 1],
                        sig.iter().map(|&v| (v * 100.0).trunc() as i16).collect(),
                    ),
                ),
                (
                    "z",
                    MatArray::Complex(vec![1, 2], vec![1.0, 0.0], vec![2.0, 3.0]),
                ),
            ],
            false,
        ),
        "two_signals.mat" => write_mat(
            &[
                ("Channel_1", column(&sig)),
                (
                    "Channel_2",
                    column(&sig.iter().map(|v| -v).collect::<Vec<_>>()),
                ),
                ("c", MatArray::Cell(vec![row(&sig[..100]), text("label")])),
            ],
            false,
        ),
        other => panic!("no fixture {other}"),
    }
}
