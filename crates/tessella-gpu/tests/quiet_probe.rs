//! Probing for a GPU prints nothing: on a machine without a display (XDG_RUNTIME_DIR unset),
//! Vulkan's Wayland surface support used to print `error: XDG_RUNTIME_DIR is invalid or not set`
//! from inside the driver, once per probe, into every caller's stderr (the Python package's
//! default backend included).
use std::process::Command;
use tessella_gpu::{AdapterChoice, GpuContext};

const CHILD: &str = "TESSELLA_QUIET_PROBE_CHILD";

/// In the child process: every kind of probe, twice.
#[test]
fn probe_child() {
    if std::env::var_os(CHILD).is_none() {
        return;
    }
    for _ in 0..2 {
        for choice in [
            AdapterChoice::Hardware,
            AdapterChoice::Auto,
            AdapterChoice::Software,
        ] {
            let _ = GpuContext::new(choice).map(|ctx| ctx.adapter_label());
        }
    }
    println!("probed");
}

#[test]
fn probing_a_gpu_without_a_display_prints_nothing() {
    let output = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", "probe_child", "--nocapture", "--test-threads=1"])
        .env(CHILD, "1")
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stdout}\n{stderr}");
    assert!(stdout.contains("probed"), "{stdout}");
    assert!(!stderr.contains("XDG_RUNTIME_DIR"), "{stderr}");
    assert!(stderr.trim().is_empty(), "the probe printed: {stderr}");
}
