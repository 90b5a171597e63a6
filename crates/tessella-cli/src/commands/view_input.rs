//! `tessella view`'s input mapping, free of any window: keys, drags and the wheel turned into
//! the parameter changes `Viewer::set` takes (the web page's names and step sizes, web/src/main.js).

use serde_json::{json, Map, Value};
use tessella_core::{Named, Scheme};
use tessella_viewer::{Animation, Params};

/// The keys the viewer answers to, as the window reports them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    Left,
    Right,
    Up,
    Down,
    Tab,
    Escape,
    /// A key that types this character (`+`, `w`, `1`, ...).
    Char(char),
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Modifiers {
    pub shift: bool,
    pub alt: bool,
}

/// What a key asks for.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Parameter changes for `Viewer::set`.
    Set(Map<String, Value>),
    Screenshot,
    Quit,
}

/// Degrees of orbit per pixel dragged (the page's).
pub const ORBIT_PER_PIXEL: f32 = 0.4;
const MIN_ZOOM: f32 = 0.05;
const MAX_ZOOM: f32 = 200.0;

fn changes(value: Value) -> Map<String, Value> {
    match value {
        Value::Object(map) => map,
        _ => Map::new(),
    }
}

/// Dragging by `(dx, dy)` pixels: right turns the camera's yaw down, down raises the pitch
/// (kept within ±89°).
pub fn orbit(p: &Params, dx: f32, dy: f32) -> Map<String, Value> {
    let pitch = (p.pitch + dy * ORBIT_PER_PIXEL).clamp(-89.0, 89.0);
    changes(json!({"yaw": p.yaw - dx * ORBIT_PER_PIXEL, "pitch": pitch}))
}

/// Panning by `(dx, dy)` pixels of a view `height` pixels high: the mesh follows the pointer.
pub fn pan(p: &Params, dx: f32, dy: f32, height: u32) -> Map<String, Value> {
    let k = 2.0 / height.max(1) as f32 / p.zoom;
    changes(json!({"pan": [p.pan[0] - dx * k, p.pan[1] + dy * k]}))
}

/// Zooming by `factor`, within 0.05..=200.
pub fn zoom_by(p: &Params, factor: f32) -> Map<String, Value> {
    changes(json!({"zoom": (p.zoom * factor).clamp(MIN_ZOOM, MAX_ZOOM)}))
}

/// The wheel turned by `lines` (positive: away from the user, zooming in), as the page's
/// `exp(-deltaY / 1000)` with 100 pixels a line.
pub fn wheel(p: &Params, lines: f32) -> Map<String, Value> {
    zoom_by(p, (lines * 0.1).exp())
}

/// The scheme after `p.scheme` in `Scheme::ALL` (`step` -1: before), wrapping.
fn step_scheme(p: &Params, step: isize) -> &'static str {
    let all = Scheme::ALL;
    let here = all
        .iter()
        .position(|s| s.name() == p.scheme.name())
        .unwrap_or(0) as isize;
    all[(here + step).rem_euclid(all.len() as isize) as usize].name()
}

/// Whether a held `key` acts again on each repeat: the camera keys do; toggles, steps,
/// screenshots and quitting act once per press.
pub fn repeats(key: Key) -> bool {
    matches!(
        key,
        Key::Left | Key::Right | Key::Up | Key::Down | Key::Char('+' | '=' | '-')
    )
}

/// Whether a key press acts. `synthetic` presses are the window system's report of keys that
/// were already held when the window gained focus (winit sends one for each): the person
/// pressed them for another window, or the press itself is on its way as a real event too, so
/// acting on both would step a level twice. Repeats act only for keys that `repeats`.
pub fn acts(key: Key, repeat: bool, synthetic: bool) -> bool {
    !synthetic && (!repeat || repeats(key))
}

/// What `,` and `.` step a paused clip by, seconds: a frame at 24 fps.
const CLIP_STEP: f32 = 1.0 / 24.0;

/// What `key` does with modifiers `m` to parameters `p` in a view `height` pixels high; `None`
/// for keys without a meaning.
pub fn key(p: &Params, key: Key, m: Modifiers, height: u32) -> Option<Action> {
    let step = if m.shift { 20.0 } else { 5.0 };
    let orbit_or_pan = |dx: f32, dy: f32| {
        if m.alt {
            pan(p, dx * 4.0, dy * 4.0, height)
        } else {
            orbit(p, dx / ORBIT_PER_PIXEL, dy / ORBIT_PER_PIXEL)
        }
    };
    let set = |v: Value| Some(Action::Set(changes(v)));
    match key {
        Key::Left => Some(Action::Set(orbit_or_pan(-step, 0.0))),
        Key::Right => Some(Action::Set(orbit_or_pan(step, 0.0))),
        Key::Up => Some(Action::Set(orbit_or_pan(0.0, -step))),
        Key::Down => Some(Action::Set(orbit_or_pan(0.0, step))),
        Key::Tab => {
            let scheme = step_scheme(p, if m.shift { -1 } else { 1 });
            set(json!({"scheme": scheme, "panels": []}))
        }
        Key::Escape | Key::Char('q') => Some(Action::Quit),
        Key::Char('+') | Key::Char('=') => Some(Action::Set(zoom_by(p, 1.1))),
        Key::Char('-') => Some(Action::Set(zoom_by(p, 1.0 / 1.1))),
        Key::Char('w') => set(json!({"wireframe": !p.wireframe})),
        Key::Char('a') => {
            let next = if p.animate == Animation::None {
                "twist"
            } else {
                "none"
            };
            set(json!({ "animate": next }))
        }
        Key::Char('s') => Some(Action::Screenshot),
        // A clip: play and pause, or step one frame (1/24 s) and pause.
        Key::Char(' ') if p.clip.is_some() => set(json!({"playing": !p.playing})),
        Key::Char(',') if p.clip.is_some() => {
            set(json!({"time": (p.time - CLIP_STEP).max(0.0), "playing": false}))
        }
        Key::Char('.') if p.clip.is_some() => {
            set(json!({"time": p.time + CLIP_STEP, "playing": false}))
        }
        // One whole level up or down from wherever a fractional level is.
        Key::Char(']') => set(json!({"level": p.level.floor() + 1.0})),
        Key::Char('[') => set(json!({"level": (p.level.ceil() - 1.0).max(1.0)})),
        // A scheme of its own: side-by-side panels (--compare) end.
        Key::Char(c @ '1'..='9') => {
            let i = c as usize - '1' as usize;
            Scheme::ALL
                .get(i)
                .and_then(|s| set(json!({"scheme": s.name(), "panels": []})))
        }
        Key::Char(_) => None,
    }
}
