//! The command line as a user meets it: clap's help, version and usage errors, exit statuses,
//! `preset NAME | run -`, and `run --format csv` (the README's columns).
#![cfg(not(target_arch = "wasm32"))]

use confset::presets;
use serde_json::Value;
use std::io::Write;
use std::process::{Child, Command, Output, Stdio};

/// `confset ARGS` with `stdin` (none: an empty one): its status, stdout and stderr.
pub(crate) fn confset(args: &[&str], stdin: Option<&[u8]>) -> Output {
    let mut c = spawn(args);
    let mut input = c.stdin.take().expect("stdin");
    if let Some(bytes) = stdin {
        input.write_all(bytes).expect("write stdin");
    }
    drop(input);
    c.wait_with_output().expect("confset finishes")
}

/// `confset ARGS` started with its stdin, stdout and stderr piped.
pub(crate) fn spawn(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_confset"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the confset binary runs")
}

/// `confset ARGS` with `stdin` exits with `code`: its output and its stderr as text.
fn exits_with(code: i32, args: &[&str], stdin: Option<&[u8]>) -> (Output, String) {
    let o = confset(args, stdin);
    let err = text(&o.stderr);
    assert_eq!(
        o.status.code(),
        Some(code),
        "confset {}: {err}",
        args.join(" ")
    );
    (o, err)
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn help_and_version_exit_zero_on_every_subcommand() {
    let top = confset(&["--help"], None);
    assert_eq!(top.status.code(), Some(0), "{}", text(&top.stderr));
    let help = text(&top.stdout);
    assert!(help.contains("Usage: confset <COMMAND>"), "{help}");
    assert!(help.contains("Exit status: 0 done; 1"), "{help}");
    for sub in [
        "presets",
        "preset",
        "run",
        "experiment",
        "merge",
        "figure",
        "figures",
        "completions",
    ] {
        assert!(
            help.contains(&format!("  {sub} ")),
            "--help lists {sub}: {help}"
        );
        let o = confset(&[sub, "--help"], None);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{sub} --help: {}",
            text(&o.stderr)
        );
        assert!(
            text(&o.stdout).contains("Example"),
            "{sub} --help has examples: {}",
            text(&o.stdout)
        );
    }
    let v = confset(&["--version"], None);
    assert_eq!(v.status.code(), Some(0));
    assert_eq!(
        text(&v.stdout).trim(),
        format!("confset {}", env!("CARGO_PKG_VERSION"))
    );
}

#[test]
fn usage_errors_exit_two_with_clap_messages_and_refused_input_exits_one() {
    for (args, says) in [
        (&["--frobnicate"][..], "unexpected argument '--frobnicate'"),
        (&["bogus"][..], "unrecognized subcommand 'bogus'"),
        (
            &["run"][..],
            "the following required arguments were not provided",
        ),
        (
            &["run", "--preset", "nope"][..],
            "invalid value 'nope' for '--preset <NAME>'",
        ),
        (
            &["run", "--preset", "scf-scalar", "--format", "xml"][..],
            "invalid value 'xml'",
        ),
        (
            &["experiment", "--preset", "ubb-track", "--shard", "4/4"][..],
            "0 ≤ i < N",
        ),
        (
            &[
                "figure",
                "--preset",
                "scf-scalar",
                "-o",
                "x.svg",
                "--size",
                "9x9",
            ][..],
            "16 to 8192",
        ),
        (
            &[
                "figure",
                "--preset",
                "scf-scalar",
                "-o",
                "x.svg",
                "--time",
                "0",
            ][..],
            "--time",
        ),
        (
            &["run", "a.json", "--preset", "scf-scalar"][..],
            "cannot be used with",
        ),
    ] {
        let (o, err) = exits_with(2, args, None);
        assert!(
            err.starts_with("error: "),
            "confset {}: {err}",
            args.join(" ")
        );
        assert!(err.contains(says), "confset {}: {err}", args.join(" "));
        assert!(o.stdout.is_empty());
    }
    // The core refuses: status 1 and the field's message.
    for (args, stdin, says) in [
        (
            &["run", "-"][..],
            &br#"{"method": 1}"#[..],
            "method must be one of",
        ),
        (&["run", "-"][..], &b"not json"[..], "scenario"),
        (
            &[
                "figure",
                "--preset",
                "scf-scalar",
                "-o",
                "x.svg",
                "--panel",
                "ubbset",
            ][..],
            &b""[..],
            "--panel ubbset is not a panel of the method \"scf\"",
        ),
    ] {
        let (_, err) = exits_with(1, args, Some(stdin));
        assert!(err.contains(says), "confset {}: {err}", args.join(" "));
    }
}

#[test]
fn preset_piped_into_run_gives_the_presets_report() {
    for name in ["scf-scalar", "lscr-ma1", "ubb-track"] {
        let p = confset(&["preset", name], None);
        assert_eq!(p.status.code(), Some(0), "{}", text(&p.stderr));
        let scenario: Value = serde_json::from_slice(&p.stdout).expect("preset prints JSON");
        assert_eq!(
            scenario,
            serde_json::to_value(presets::get(name).unwrap()).unwrap()
        );
        let piped = confset(&["run", "-"], Some(&p.stdout));
        assert_eq!(piped.status.code(), Some(0), "{}", text(&piped.stderr));
        let direct = confset(&["run", "--preset", name], None);
        assert_eq!(text(&piped.stdout), text(&direct.stdout), "{name}");
        assert!(!piped.stdout.is_empty());
    }
}

/// The README's columns per method, and each row's numbers are the JSON report's.
#[test]
fn csv_has_the_documented_columns_and_the_reports_numbers() {
    let cases: [(&str, &str, &[&str]); 5] = [
        (
            "scf-scalar",
            "t,y_1,x_1,kf_1,kf_volume,kf_holds,scf_1,scf_volume,scf_holds",
            &["steps"],
        ),
        (
            "lscr-ma1",
            "time,M,q,level,area,bounded,x_1,x_2,holds",
            &["lscr"],
        ),
        (
            "glls-saturate",
            "s,log10_sigma_1,log10_sigma_2,log10_sigma_3,log10_floor,log10_kappa_lls_current,\
             log10_kappa_glls_past,log10_kappa_glls_current,index",
            &["glls"],
        ),
        (
            "uniform-paper",
            "t,y_1,x_1,x_2,x_map_1,x_map_2,xr_1,xr_2,yr_1,y_pred_1,kf_1,kf_2",
            &["uniform", "steps"],
        ),
        (
            "ubb-track",
            "k,center_1,center_2,lo_1,lo_2,hi_1,hi_2,radius,kf_1,kf_2,x_1,x_2,holds,kf_holds",
            &["ubb", "track"],
        ),
    ];
    for (name, header, rows_at) in cases {
        let o = confset(&["run", "--preset", name, "--format", "csv"], None);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
        let csv = text(&o.stdout);
        // The report's warnings stand above the header (uniform-paper: an estimate on ±5).
        let mut lines = csv.lines().skip_while(|l| l.starts_with("# warning: "));
        assert_eq!(lines.next(), Some(header), "{name}");
        let columns: Vec<&str> = header.split(',').collect();
        let rows: Vec<Vec<Option<f64>>> = lines
            .map(|l| {
                let cells: Vec<&str> = l.split(',').collect();
                assert_eq!(cells.len(), columns.len(), "{name}: {l}");
                cells
                    .iter()
                    .map(|c| (!c.is_empty()).then(|| c.parse::<f64>().expect("a number")))
                    .collect()
            })
            .collect();
        let report = serde_json::to_value(presets::get(name).unwrap().run().unwrap()).unwrap();
        let mut block = &report;
        for k in rows_at {
            block = &block[k];
        }
        // One row per time step of the report (LSCR: its one region).
        let want_rows = block.as_array().map_or(1, |a| a.len());
        let want_rows = if name == "glls-saturate" {
            block["curves"]["log10_sigma"].as_array().unwrap().len()
        } else {
            want_rows
        };
        assert_eq!(rows.len(), want_rows, "{name}");
        // The numbers are the report's: the first column (time) and one estimate column.
        let col = |c: &str| columns.iter().position(|x| *x == c).unwrap();
        let last = rows.last().unwrap();
        match name {
            "scf-scalar" => {
                let st = block.as_array().unwrap().last().unwrap();
                assert_eq!(last[0], st["t"].as_f64());
                assert_eq!(last[col("scf_1")], st["scf"]["center"][0].as_f64());
            }
            "lscr-ma1" => {
                assert_eq!(last[col("time")], block["time"].as_f64());
                assert_eq!(last[col("area")], block["area"].as_f64());
            }
            "glls-saturate" => {
                let s = rows.len() - 1;
                assert_eq!(last[col("index")], block["index"][s].as_f64());
                assert_eq!(
                    last[col("log10_sigma_1")],
                    block["curves"]["log10_sigma"][s][0].as_f64()
                );
            }
            "uniform-paper" => {
                let st = block.as_array().unwrap().last().unwrap();
                assert_eq!(last[0], st["t"].as_f64());
                assert_eq!(last[col("x_map_2")], st["x"][1].as_f64());
            }
            _ => {
                let st = block.as_array().unwrap().last().unwrap();
                assert_eq!(last[0], st["k"].as_f64());
                assert_eq!(last[col("hi_2")], st["hi"][1].as_f64());
            }
        }
    }
}

#[test]
fn completions_for_bash_name_every_subcommand() {
    let o = confset(&["completions", "bash"], None);
    assert_eq!(o.status.code(), Some(0));
    let script = text(&o.stdout);
    for sub in ["experiment", "merge", "figure", "preset"] {
        assert!(script.contains(sub), "{sub}");
    }
}

/// `figure -o FILE.png` rasterizes the SVG at `--scale` (default 2): a PNG of twice the size.
#[test]
fn figure_writes_png_at_the_scale() {
    let dir = std::env::temp_dir().join(format!("confset-cli-png-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("fig.png");
    let out = out.to_str().unwrap();
    let figure = |extra: &[&str]| {
        let mut args = vec!["figure", "--preset", "lscr-ma1", "-o", out];
        args.extend_from_slice(extra);
        confset(&args, None)
    };
    let o = figure(&["--size", "480x320"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    let png = std::fs::read(out).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height, big-endian, at bytes 16..24.
    let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
    assert_eq!((w, h), (960, 640));
    let o = figure(&["--scale", "9"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("from 0.25 to 8"));
    std::fs::remove_dir_all(&dir).ok();
}
