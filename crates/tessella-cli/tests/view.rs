//! `tessella view`: the input mapping, the refusals without a display, and the window's picture
//! under a virtual X server (xvfb-run) against `tessella render`'s.
#![cfg(feature = "view")]

#[path = "../src/commands/view_input.rs"]
#[allow(dead_code)]
mod view_input;

use serde_json::{Map, Value};
use std::path::Path;
use std::process::{Command, Output};
use tessella_core::{samples, Scheme};
use tessella_viewer::{Animation, Params};
use view_input::{Action, Key, Modifiers};

const NONE: Modifiers = Modifiers {
    shift: false,
    alt: false,
};
const SHIFT: Modifiers = Modifiers {
    shift: true,
    alt: false,
};
const ALT: Modifiers = Modifiers {
    shift: false,
    alt: true,
};

/// The parameters after `changes`, which `Viewer::set` must accept as they are.
fn after(p: &Params, changes: &Map<String, Value>) -> Params {
    p.apply(changes)
        .unwrap_or_else(|e| panic!("{changes:?} refused: {e}"))
}

fn press(p: &Params, key: Key, m: Modifiers) -> Params {
    match view_input::key(p, key, m, 600) {
        Some(Action::Set(changes)) => after(p, &changes),
        other => panic!("{key:?}: {other:?}"),
    }
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() < 1e-4
}

#[test]
fn dragging_orbits_and_pans_as_the_page_does() {
    let p = Params::default();
    // Right by 10 pixels: yaw down by 4 degrees; down by 5: pitch up by 2.
    let q = after(&p, &view_input::orbit(&p, 10.0, 5.0));
    assert!(close(q.yaw, p.yaw - 4.0), "{}", q.yaw);
    assert!(close(q.pitch, p.pitch + 2.0), "{}", q.pitch);
    assert_eq!(q.pan, p.pan);
    // The pitch stops short of the poles.
    let q = after(&p, &view_input::orbit(&p, 0.0, 1000.0));
    assert!(close(q.pitch, 89.0), "{}", q.pitch);
    let q = after(&p, &view_input::orbit(&p, 0.0, -1000.0));
    assert!(close(q.pitch, -89.0), "{}", q.pitch);
    // Panning 60 pixels of 600 at zoom 1: a fifth of the framed radius, the mesh follows.
    let q = after(&p, &view_input::pan(&p, 60.0, -60.0, 600));
    assert!(
        close(q.pan[0], -0.2) && close(q.pan[1], -0.2),
        "{:?}",
        q.pan
    );
    assert_eq!((q.yaw, q.pitch), (p.yaw, p.pitch));
    // Zoomed in twice as far, the same drag pans half as much.
    let z = Params {
        zoom: 2.0,
        ..p.clone()
    };
    let q = after(&z, &view_input::pan(&z, 60.0, 0.0, 600));
    assert!(close(q.pan[0], -0.1), "{:?}", q.pan);
    // The wheel away from the user zooms in, towards zooms out, within bounds.
    assert!(after(&p, &view_input::wheel(&p, 1.0)).zoom > p.zoom);
    assert!(after(&p, &view_input::wheel(&p, -1.0)).zoom < p.zoom);
    assert!(close(after(&p, &view_input::wheel(&p, 1000.0)).zoom, 200.0));
    assert!(close(after(&p, &view_input::wheel(&p, -1000.0)).zoom, 0.05));
}

#[test]
fn clip_keys_play_pause_and_step() {
    let p = Params::default();
    // Without a clip the keys mean nothing.
    for key in [' ', ',', '.'] {
        assert!(view_input::key(&p, Key::Char(key), NONE, 600).is_none());
    }
    let p = after(
        &p,
        &view_input_changes(serde_json::json!({"clip": "wave", "time": 1.0})),
    );
    assert!(p.playing);
    let paused = press(&p, Key::Char(' '), NONE);
    assert!(!paused.playing);
    assert!(press(&paused, Key::Char(' '), NONE).playing);
    let back = press(&p, Key::Char(','), NONE);
    assert!(close(back.time, 1.0 - 1.0 / 24.0) && !back.playing);
    let on = press(&back, Key::Char('.'), NONE);
    assert!(close(on.time, 1.0));
    // Never before the clip's start.
    let start = after(&p, &view_input_changes(serde_json::json!({"time": 0.01})));
    assert_eq!(press(&start, Key::Char(','), NONE).time, 0.0);
}

fn view_input_changes(value: Value) -> Map<String, Value> {
    value.as_object().expect("an object").clone()
}

#[test]
fn keys_change_the_parameters_the_page_changes() {
    let p = Params::default();
    assert!(close(press(&p, Key::Left, NONE).yaw, p.yaw + 5.0));
    assert!(close(press(&p, Key::Right, SHIFT).yaw, p.yaw - 20.0));
    assert!(close(press(&p, Key::Up, NONE).pitch, p.pitch - 5.0));
    assert!(close(press(&p, Key::Down, NONE).pitch, p.pitch + 5.0));
    // Alt + arrows pan, leaving the orbit alone.
    let q = press(&p, Key::Left, ALT);
    assert!(q.pan[0] > 0.0 && q.pan[1] == 0.0, "{:?}", q.pan);
    assert_eq!(q.yaw, p.yaw);
    let q = press(&p, Key::Up, ALT);
    assert!(q.pan[1] < 0.0 && q.pan[0] == 0.0, "{:?}", q.pan);
    assert!(close(press(&p, Key::Char('+'), NONE).zoom, 1.1));
    assert!(close(press(&p, Key::Char('='), NONE).zoom, 1.1));
    assert!(close(press(&p, Key::Char('-'), NONE).zoom, 1.0 / 1.1));
    let wire = press(&p, Key::Char('w'), NONE);
    assert!(wire.wireframe);
    assert!(!press(&wire, Key::Char('w'), NONE).wireframe);
    // Levels: whole steps, from a fractional level too, never below 1.
    assert_eq!(press(&p, Key::Char(']'), NONE).level, 9.0);
    assert_eq!(press(&p, Key::Char('['), NONE).level, 7.0);
    let frac = Params {
        level: 5.5,
        ..p.clone()
    };
    assert_eq!(press(&frac, Key::Char(']'), NONE).level, 6.0);
    assert_eq!(press(&frac, Key::Char('['), NONE).level, 5.0);
    let one = Params {
        level: 1.0,
        ..p.clone()
    };
    assert_eq!(press(&one, Key::Char('['), NONE).level, 1.0);
    // Schemes: 1..7 pick one (ending side-by-side panels), Tab steps and wraps.
    let panels = Params {
        panels: vec![Scheme::Flat, Scheme::Pn],
        ..p.clone()
    };
    let q = press(&panels, Key::Char('1'), NONE);
    assert_eq!(q.scheme, Scheme::Flat);
    assert!(q.panels.is_empty());
    assert_eq!(press(&p, Key::Char('7'), NONE).scheme, Scheme::Quadratic);
    assert_eq!(press(&p, Key::Char('4'), NONE).scheme, Scheme::Png1);
    assert_eq!(view_input::key(&p, Key::Char('8'), NONE, 600), None);
    assert_eq!(press(&p, Key::Tab, NONE).scheme, Scheme::Png1);
    assert!(matches!(
        press(&p, Key::Tab, SHIFT).scheme,
        Scheme::Phong { .. }
    ));
    let last = press(&p, Key::Char('7'), NONE);
    assert_eq!(press(&last, Key::Tab, NONE).scheme, Scheme::Flat);
    // The twist animation toggles.
    let twist = press(&p, Key::Char('a'), NONE);
    assert_eq!(twist.animate, Animation::Twist);
    assert_eq!(press(&twist, Key::Char('a'), NONE).animate, Animation::None);
    for (key, action) in [
        (Key::Char('s'), Action::Screenshot),
        (Key::Char('q'), Action::Quit),
        (Key::Escape, Action::Quit),
    ] {
        assert_eq!(view_input::key(&p, key, NONE, 600), Some(action));
    }
    // A press acts once; held, only the camera keys act again; a key that was already held
    // when the window gained focus (winit's synthetic press) never acts.
    for key in [
        Key::Char(']'),
        Key::Char('w'),
        Key::Char('s'),
        Key::Tab,
        Key::Left,
    ] {
        assert!(view_input::acts(key, false, false), "{key:?}");
        assert!(!view_input::acts(key, false, true), "{key:?} synthetic");
        assert!(
            !view_input::acts(key, true, true),
            "{key:?} synthetic repeat"
        );
    }
    for (key, again) in [
        (Key::Char(']'), false),
        (Key::Char('w'), false),
        (Key::Char('q'), false),
        (Key::Left, true),
        (Key::Char('+'), true),
    ] {
        assert_eq!(
            view_input::acts(key, true, false),
            again,
            "{key:?} repeated"
        );
    }
    assert_eq!(view_input::key(&p, Key::Char('x'), NONE, 600), None);
    // Held down, the camera keys repeat; the others act once.
    assert!(view_input::repeats(Key::Left) && view_input::repeats(Key::Char('-')));
    for k in ['w', 's', ']', '1', 'a', 'q'] {
        assert!(!view_input::repeats(Key::Char(k)), "{k}");
    }
    assert!(!view_input::repeats(Key::Tab));
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `tessella ARGS` without any display.
fn headless(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the binary runs")
}

#[test]
fn without_a_display_it_says_so_and_exits_1() {
    for args in [&["view"][..], &["view", "--frames", "1", "--level", "3"]] {
        let out = headless(args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains("neither DISPLAY nor WAYLAND_DISPLAY is set"),
            "{args:?}: {err}"
        );
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn a_display_nobody_answers_on_is_an_error_not_a_panic() {
    let out = Command::new(env!("CARGO_BIN_EXE_tessella"))
        .args(["view", "--frames", "1"])
        .env("DISPLAY", ":7391")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the binary runs");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with("error: cannot open a window (DISPLAY=:7391, WAYLAND_DISPLAY unset)"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_files_and_parameters_are_refused_before_a_window_opens() {
    let dir = tempfile::tempdir().unwrap();
    let broken = dir.path().join("broken.obj");
    std::fs::write(&broken, "v 0 0 0\nf 1 2 3\n").unwrap();
    let broken = broken.to_str().unwrap();
    // The CLI's usual message: the one `tessella render` gives for the same file.
    let render = headless(&["render", broken, "-o", "x.png"]);
    let view = headless(&["view", broken]);
    assert_eq!(view.status.code(), Some(1));
    assert_eq!(stderr(&view), stderr(&render));
    assert!(stderr(&view).contains("broken.obj"), "{}", stderr(&view));
    let missing = headless(&["view", "no/such/mesh.obj"]);
    assert_eq!(missing.status.code(), Some(1));
    assert!(
        stderr(&missing).contains("mesh.obj"),
        "{}",
        stderr(&missing)
    );
    for (args, message) in [
        (
            &["view", "--level", "0"][..],
            "level: must be a finite number above 0",
        ),
        (&["view", "--animate", "spin"], "animate: unknown animation"),
        (&["view", ANIMATED, "--clip", "dance"], "clip: "),
        (
            &["view", ANIMATED, "--clip", "wave", "--time", "-2"],
            "time: ",
        ),
        (&["view", "--clip", "wave"], "clip: "),
        (
            &["view", "--displace", "sine:0.1,5", "--lod", "screen:4"],
            "displace:",
        ),
    ] {
        let out = headless(args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains(message), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

fn run(command: &mut Command) -> Output {
    let out = command.output().expect("the command runs");
    assert!(
        out.status.success(),
        "{command:?}: {}\n{}",
        out.status,
        stderr(&out)
    );
    assert!(!stderr(&out).contains("panicked"), "{}", stderr(&out));
    out
}

/// Pixels that are not the white background.
fn mask(picture: &image::RgbaImage) -> Vec<bool> {
    picture.pixels().map(|p| p.0[..3] != [255; 3]).collect()
}

fn iou(a: &[bool], b: &[bool]) -> f64 {
    let both = a.iter().zip(b).filter(|(x, y)| **x && **y).count();
    let either = a.iter().zip(b).filter(|(x, y)| **x || **y).count();
    both as f64 / either.max(1) as f64
}

/// One virtual X server at a time: `xvfb-run -a` started twice at once may pick one number.
static XVFB: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// `program` on the PATH.
fn on_path(program: &str) -> Option<std::path::PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(program))
        .find(|p| p.is_file())
}

/// The window tests' tool `program`, or `None` (the test skips, saying why) where
/// `TESSELLA_NO_DISPLAY_TESTS=1` says to go without; a missing tool otherwise fails the test.
fn display_tool(program: &str) -> Option<std::path::PathBuf> {
    if let Some(path) = on_path(program) {
        return Some(path);
    }
    if std::env::var("TESSELLA_NO_DISPLAY_TESTS").as_deref() == Ok("1") {
        eprintln!(
            "skipped: {program} is not installed and TESSELLA_NO_DISPLAY_TESTS=1 says to go \
             without the window tests"
        );
        return None;
    }
    panic!(
        "{program} is not installed: run scripts/test.sh (it installs xvfb, xdotool and xwd as \
         root), or apt-get install -y xvfb xauth xdotool x11-apps; TESSELLA_NO_DISPLAY_TESTS=1 skips \
         this test"
    );
}

/// `tessella render`'s picture of `mesh` with `args`.
fn render(dir: &Path, mesh: &Path, args: &[&str]) -> image::RgbaImage {
    let path = dir.join("render.png");
    run(Command::new(env!("CARGO_BIN_EXE_tessella"))
        .arg("render")
        .arg(mesh)
        .arg("-o")
        .arg(&path)
        .args(args));
    let picture = image::open(&path).unwrap().to_rgba8();
    std::fs::remove_file(&path).unwrap();
    picture
}

/// Asserts two pictures of one view agree: the silhouettes (IoU above 0.99) and the colours.
fn assert_same_view(what: &str, window: &image::RgbaImage, render: &image::RgbaImage) {
    assert_eq!(window.dimensions(), render.dimensions(), "{what}");
    let (a, b) = (mask(window), mask(render));
    let covered = a.iter().filter(|x| **x).count();
    assert!(
        covered > a.len() / 10,
        "{what}: the window's picture is nearly blank"
    );
    let overlap = iou(&a, &b);
    // A swapped red and blue would pass the silhouette.
    let differing = window
        .pixels()
        .zip(render.pixels())
        .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 48))
        .count();
    eprintln!(
        "{what}: silhouette IoU {overlap:.5}, {differing} of {} pixels differ in colour",
        a.len()
    );
    assert!(overlap > 0.99, "{what}: silhouette IoU {overlap}");
    assert!(
        differing <= a.len() / 50,
        "{what}: {differing} of {} pixels differ in colour",
        a.len()
    );
}

const CAMERA: [&str; 10] = [
    "--size", "320x240", "--yaw", "40", "--pitch", "15", "--scheme", "pn", "--level", "8",
];

/// The bundled animated sample: three clips (wave, hop, breathe).
const ANIMATED: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../samples/animated-creature.glb"
);

fn creature() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples/creature.obj")
}

/// The window's screenshot of `mesh` (or the first sample when `None`) against `tessella
/// render`'s picture of `reference` with the same scheme, level, camera and size.
fn compare_window_with_render(dir: &Path, xvfb: &Path, mesh: Option<&Path>, reference: &Path) {
    let shot = dir.join("window.png");
    let mut view = Command::new(xvfb);
    view.args(["-a", "-s", "-screen 0 1024x768x24"])
        .arg(env!("CARGO_BIN_EXE_tessella"))
        .arg("view");
    if let Some(mesh) = mesh {
        view.arg(mesh);
    }
    view.args(["--frames", "3", "--screenshot"])
        .arg(&shot)
        .args(CAMERA);
    run(&mut view);
    // Nothing but the picture: the screenshot's temporary file was renamed into place.
    let names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".png") || n.ends_with(".tmp"))
        .collect();
    assert_eq!(names, ["window.png"]);
    let window = image::open(&shot).unwrap().to_rgba8();
    std::fs::remove_file(&shot).unwrap();
    assert_eq!(window.dimensions(), (320, 240));
    let render = render(dir, reference, &CAMERA);
    assert_same_view(&reference.display().to_string(), &window, &render);
}

#[test]
fn the_window_draws_what_tessella_render_draws() {
    let _one = XVFB.lock().unwrap_or_else(|p| p.into_inner());
    let Some(xvfb) = display_tool("xvfb-run") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    compare_window_with_render(dir.path(), &xvfb, Some(&creature()), &creature());
    // No file: the first bundled sample.
    let first = dir.path().join("first.ply");
    let mesh = samples::by_name(tessella_viewer::FIRST_SAMPLE).unwrap();
    tessella_io::write_mesh(&first, (&mesh).into(), &Default::default()).unwrap();
    compare_window_with_render(dir.path(), &xvfb, None, &first);
}

/// Keys typed into the window (xdotool) reach the viewer: `w` wireframe, `]` a level up, `s`
/// a screenshot, `q` quits; the screenshot and the window as the X server shows it (xwd) are
/// `tessella render --wireframe --level 9`'s view, and again after the window is resized.
#[test]
fn keys_typed_into_the_window_change_the_view() {
    let _one = XVFB.lock().unwrap_or_else(|p| p.into_inner());
    let (Some(xvfb), Some(_), Some(_)) = (
        display_tool("xvfb-run"),
        display_tool("xdotool"),
        display_tool("xwd"),
    ) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("keys.png");
    // Waits on the window and the file rather than sleeping a fixed time; gives up after 60 s.
    // `]` is held down before the window has focus and let go after (one xdotool client: the
    // server lets go of a client's held keys when it disconnects). The window system reports
    // it as held when focus arrives (winit's synthetic press), which must not step the level;
    // only the `]` typed after it does. The X server's autorepeat is off (-ardelay), so the
    // held key sends no presses of its own.
    let script = r#"
        "$TESSELLA" view "$MESH" --screenshot "$SHOT" "$@" & pid=$!
        wid=$(timeout 60 xdotool search --sync --name "^tessella view" | head -n 1)
        [ -n "$wid" ] || { echo "no window appeared" >&2; kill $pid; exit 1; }
        for i in $(seq 300); do xdotool getwindowname "$wid" | grep -q "level 8 " && break; sleep 0.1; done
        xdotool keydown bracketright windowfocus --sync "$wid" sleep 1 keyup bracketright
        xdotool key --window "$wid" w bracketright s
        for i in $(seq 600); do [ -s "$SHOT" ] && break; sleep 0.1; done
        # The title changes after a frame of the new level is presented; then read the window.
        for i in $(seq 600); do xdotool getwindowname "$wid" | grep -q "level 9 " && break; sleep 0.1; done
        title=$(xdotool getwindowname "$wid")
        case "$title" in *"level 9 "*) ;; *) echo "the title is $title" >&2; kill $pid; exit 1;; esac
        sleep 0.5
        xwd -id "$wid" -silent > "$XWD"
        # Resized, the window draws at its new size.
        mv "$SHOT" "$FIRST"
        xdotool windowsize --sync "$wid" 400 300
        xdotool key --window "$wid" s
        for i in $(seq 600); do [ -s "$SHOT" ] && break; sleep 0.1; done
        xdotool key --window "$wid" q
        # Bounded: a window that missed the q fails the test instead of hanging it.
        for i in $(seq 300); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
        if kill -0 $pid 2>/dev/null; then echo "the window did not quit on q" >&2; kill $pid; exit 1; fi
        wait $pid
    "#;
    let out = run(Command::new(&xvfb)
        .args([
            "-a",
            "-s",
            "-screen 0 1024x768x24 -ardelay 60000",
            "bash",
            "-c",
            script,
            "keys",
        ])
        .args(CAMERA)
        .env("TESSELLA", env!("CARGO_BIN_EXE_tessella"))
        .env("MESH", creature())
        .env("SHOT", &shot)
        .env("FIRST", dir.path().join("first.png"))
        .env("XWD", dir.path().join("window.xwd")));
    let first = dir.path().join("first.png");
    assert!(first.is_file(), "no screenshot: {}", stderr(&out));
    let window = image::open(&first).unwrap().to_rgba8();
    let mut args = CAMERA.to_vec();
    args[9] = "9";
    args.push("--wireframe");
    let reference = render(dir.path(), &creature(), &args);
    assert_same_view("after w ] s", &window, &reference);
    // What the window shows: lavapipe presented the frame to the X server.
    let shown = read_xwd(&std::fs::read(dir.path().join("window.xwd")).unwrap());
    assert_same_view("the window on the X server", &shown, &reference);
    let resized = image::open(&shot).unwrap().to_rgba8();
    args[1] = "400x300";
    let bigger = render(dir.path(), &creature(), &args);
    assert_same_view("resized to 400x300", &resized, &bigger);
}

/// An `xwd` dump of a TrueColor window (32 bits a pixel) as RGBA.
fn read_xwd(bytes: &[u8]) -> image::RgbaImage {
    let word = |i: usize| u32::from_be_bytes(bytes[4 * i..4 * i + 4].try_into().unwrap());
    let (header, width, height) = (word(0) as usize, word(4), word(5));
    let (little, bits, stride) = (word(7) == 0, word(11), word(12) as usize);
    let masks = [word(14), word(15), word(16)];
    assert_eq!(bits, 32, "xwd: {bits} bits a pixel");
    let pixels = &bytes[header + 12 * word(19) as usize..];
    image::RgbaImage::from_fn(width, height, |x, y| {
        let at = y as usize * stride + 4 * x as usize;
        let raw: [u8; 4] = pixels[at..at + 4].try_into().unwrap();
        let v = if little {
            u32::from_le_bytes(raw)
        } else {
            u32::from_be_bytes(raw)
        };
        let channel = |m: u32| ((v & m) >> m.trailing_zeros()) as u8;
        image::Rgba([channel(masks[0]), channel(masks[1]), channel(masks[2]), 255])
    })
}

/// `--clip NAME --time T` opens the animated sample paused at T: two times give two poses, and
/// the same time twice the same picture (paused, the clock does not move it).
#[test]
fn a_clip_opens_paused_at_its_time() {
    let _one = XVFB.lock().unwrap_or_else(|p| p.into_inner());
    let Some(xvfb) = display_tool("xvfb-run") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let shot = |time: &str, frames: &str| {
        let path = dir.path().join(format!("clip-{time}-{frames}.png"));
        let mut view = Command::new(&xvfb);
        view.args(["-a", "-s", "-screen 0 1024x768x24"])
            .arg(env!("CARGO_BIN_EXE_tessella"))
            .args(["view", ANIMATED, "--clip", "wave", "--time", time])
            .args(["--frames", frames, "--screenshot"])
            .arg(&path)
            .args(CAMERA);
        run(&mut view);
        image::open(&path).unwrap().to_rgba8()
    };
    let at = shot("0.5", "2");
    let again = shot("0.5", "5");
    let start = shot("0", "2");
    let covered = mask(&at).iter().filter(|&&m| m).count();
    assert!(covered > 2000, "the creature covers {covered} pixels");
    assert_eq!(at, again, "a paused clip moved");
    let moved = at
        .pixels()
        .zip(start.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        moved > 200,
        "wave at 0.5 s and at 0 differ in {moved} pixels"
    );
}
