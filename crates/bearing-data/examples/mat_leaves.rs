//! Print every leaf of a MAT-file: `cargo run -p bearing-data --example mat_leaves -- FILE.mat`.
fn main() {
    let Some(p) = std::env::args().nth(1) else {
        eprintln!("usage: mat_leaves FILE.mat");
        std::process::exit(2);
    };
    let bytes = match std::fs::read(&p) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("{p}: {e}");
            std::process::exit(1);
        }
    };
    match bearing_data::read_mat_tree(&bytes) {
        Ok(leaves) => {
            for l in leaves {
                let what = match &l.value {
                    bearing_data::MatValue::Numeric { dims, values } => {
                        format!("numeric {dims:?}, first {:?}", values.first())
                    }
                    bearing_data::MatValue::Complex { dims } => format!("complex {dims:?}"),
                    bearing_data::MatValue::Text(s) => format!("text {s:?}"),
                };
                match &l.alias {
                    Some(a) => println!("{} ({a}): {what}", l.path),
                    None => println!("{}: {what}", l.path),
                }
            }
        }
        Err(e) => {
            eprintln!("{p}: {e}");
            std::process::exit(1);
        }
    }
}
