//! `tessella view`: the viewer's engine (`tessella_viewer::Viewer`) in a native window (winit),
//! presented through `tessella_viewer::present::Presenter` on the window's surface. The input
//! mapping is `view_input`'s; this module owns the window, the GPU and the frame loop.

use super::view_input::{self, Action, Key, Modifiers};
use crate::args::ViewArgs;
use anyhow::{anyhow, Context};
use serde_json::{json, Map, Value};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;
use tessella_core::Named;
use tessella_gpu::{AdapterChoice, GpuContext};
use tessella_view::RgbaImage;
use tessella_viewer::present::Presenter;
use tessella_viewer::{Animation, Params, Viewer};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{Key as WinitKey, NamedKey};
use winit::window::{Window, WindowId};

/// How often the title's fps is recomputed.
const TITLE_EVERY_MS: f64 = 500.0;
/// Frames in a row the surface may withhold a texture before `--frames` gives up.
const MAX_MISSED_FRAMES: u32 = 200;
/// Interactively, redraws asked for at once after the surface withheld a texture.
const RETRIES: u32 = 3;

pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    // Everything that can be wrong with the arguments is found before a window opens.
    let changes = changes(args)?;
    Params::default()
        .apply(&changes)
        .map_err(|e| anyhow!("{e}"))?;
    let mesh = match &args.input {
        Some(path) => {
            // The CLI's own reader first, for its usual messages on a broken file.
            super::tags::read(path)?;
            if let Some(clip) = &args.clip {
                let poser = super::pose::load(path)?;
                poser.clip_index(clip).map_err(|e| anyhow!("clip: {e}"))?;
            }
            let bytes =
                std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
            Some((path.display().to_string(), bytes))
        }
        None if args.clip.is_some() => {
            anyhow::bail!("clip: the first sample has no animation clips; give a glTF file")
        }
        None => None,
    };
    check_display()?;
    let event_loop =
        EventLoop::new().map_err(|e| anyhow!("cannot open a window ({}): {e}", displays()))?;
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::PRIMARY,
        ..wgpu::InstanceDescriptor::new_with_display_handle(Box::new(
            event_loop.owned_display_handle(),
        ))
    });
    let mut app = App {
        setup: Setup {
            instance,
            changes,
            mesh,
            size: args.size,
            frames: args.frames,
            screenshot: args.screenshot.clone(),
        },
        running: None,
        error: None,
        screenshots: 0,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| anyhow!("the window's event loop failed: {e}"))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The arguments as the viewer's parameters (the page's URL keys).
fn changes(args: &ViewArgs) -> anyhow::Result<Map<String, Value>> {
    let spacing = args.spacing.to_string();
    let tags = match &args.tags {
        Some(path) => std::fs::read_to_string(path)
            .with_context(|| format!("cannot read --tags {}", path.display()))?,
        None => String::new(),
    };
    let value = json!({
        "scheme": args.shape.scheme.0.name(),
        "level": args.level,
        "spacing": spacing,
        "lod": args.lod.as_deref().unwrap_or("fixed"),
        "alpha": args.shape.alpha,
        "normals": args.shape.normals.map_or("default", |n| n.0.name()),
        "wireframe": args.view.wireframe,
        "displace": args.displace.as_deref().unwrap_or("none"),
        "yaw": args.view.yaw,
        "pitch": args.view.pitch,
        "zoom": args.view.zoom,
        "animate": args.animate,
        "panels": args.compare.iter().map(|s| s.0.name()).collect::<Vec<_>>(),
        "tags": tags,
    });
    match value {
        Value::Object(mut map) => {
            if let Some(clip) = &args.clip {
                map.insert("clip".into(), json!(clip));
            }
            // A given time opens paused there, as the page's URL does.
            if let Some(time) = args.time {
                map.insert("time".into(), json!(time));
                map.insert("playing".into(), json!(false));
            }
            Ok(map)
        }
        _ => Err(anyhow!("the parameters are not an object")),
    }
}

/// On X11/Wayland systems, a clear message when there is no display to open a window on.
fn check_display() -> anyhow::Result<()> {
    if cfg!(all(unix, not(target_os = "macos")))
        && std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty())
        && std::env::var_os("WAYLAND_DISPLAY").is_none_or(|d| d.is_empty())
    {
        anyhow::bail!(
            "tessella view needs a display: neither DISPLAY nor WAYLAND_DISPLAY is set (run it \
             in a desktop session, or under a virtual X server: xvfb-run -a tessella view ...)"
        );
    }
    Ok(())
}

/// "DISPLAY=:0, WAYLAND_DISPLAY unset", for messages.
fn displays() -> String {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .map(|name| match std::env::var_os(name) {
            Some(v) => format!("{name}={}", v.to_string_lossy()),
            None => format!("{name} unset"),
        })
        .join(", ")
}

/// What the window is opened with.
struct Setup {
    instance: wgpu::Instance,
    changes: Map<String, Value>,
    mesh: Option<(String, Vec<u8>)>,
    size: (u32, u32),
    frames: Option<u32>,
    screenshot: Option<PathBuf>,
}

/// The open window and what draws into it.
struct Running {
    window: Arc<Window>,
    ctx: GpuContext,
    presenter: Presenter,
    viewer: Viewer,
    start: Instant,
    /// Frames presented, and in a row withheld by the surface.
    frames: u32,
    missed: u32,
    /// Frames since `fps_since` (ms), and the rate last computed.
    fps_frames: u32,
    fps_since: f64,
    fps: f64,
    title: String,
    cursor: Option<(f64, f64)>,
    buttons: [bool; 3],
    modifiers: Modifiers,
}

struct App {
    setup: Setup,
    running: Option<Running>,
    error: Option<anyhow::Error>,
    screenshots: u32,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        self.error.get_or_insert(error);
        event_loop.exit();
    }

    fn open(&self, event_loop: &ActiveEventLoop) -> anyhow::Result<Running> {
        let setup = &self.setup;
        let attributes = Window::default_attributes()
            .with_title("tessella view")
            .with_inner_size(PhysicalSize::new(setup.size.0, setup.size.1));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| anyhow!("cannot open a window: {e}"))?,
        );
        let surface = setup
            .instance
            .create_surface(window.clone())
            .map_err(|e| anyhow!("cannot draw into the window: {e}"))?;
        let ctx = pollster::block_on(GpuContext::for_surface_async(
            &setup.instance,
            Some(&surface),
            AdapterChoice::Auto,
        ))
        .context(
            "no GPU adapter can draw into this window; without a GPU install Mesa's software \
             Vulkan driver (Debian: apt-get install mesa-vulkan-drivers libvulkan1)",
        )?;
        let size = window.inner_size();
        let presenter = Presenter::new(&ctx, surface, size.width, size.height)?;
        let mut viewer = Viewer::new(ctx.clone(), presenter.view_format())?;
        viewer.resize(size.width.max(1), size.height.max(1))?;
        if let Some((name, bytes)) = &setup.mesh {
            viewer.load(name, bytes)?;
        }
        viewer.set(&setup.changes)?;
        window.request_redraw();
        Ok(Running {
            window,
            ctx,
            presenter,
            viewer,
            start: Instant::now(),
            frames: 0,
            missed: 0,
            fps_frames: 0,
            fps_since: 0.0,
            fps: 0.0,
            title: String::new(),
            cursor: None,
            buttons: [false; 3],
            modifiers: Modifiers::default(),
        })
    }

    /// Where the next screenshot goes: `--screenshot`, else a numbered file not yet there.
    fn screenshot_path(&mut self) -> PathBuf {
        if let Some(path) = &self.setup.screenshot {
            return path.clone();
        }
        loop {
            self.screenshots += 1;
            let path = PathBuf::from(format!("tessella-view-{}.png", self.screenshots));
            if !path.exists() {
                return path;
            }
        }
    }

    /// One frame; `Ok(true)` when the loop is done (`--frames` reached).
    fn redraw(&mut self) -> anyhow::Result<bool> {
        let frames = self.setup.frames;
        let Some(r) = self.running.as_mut() else {
            return Ok(false);
        };
        let time_ms = r.start.elapsed().as_secs_f64() * 1000.0;
        if !r.presenter.frame(&r.ctx, &mut r.viewer, time_ms)? {
            r.missed += 1;
            if frames.is_some() && r.missed > MAX_MISSED_FRAMES {
                anyhow::bail!(
                    "the window gave no texture to draw into {MAX_MISSED_FRAMES} times in a row"
                );
            }
            // Retry soon (an outdated surface was just reconfigured), but not forever while
            // the window is hidden: showing it again asks for a redraw.
            if frames.is_some() || r.missed <= RETRIES {
                r.window.request_redraw();
            }
            return Ok(false);
        }
        r.missed = 0;
        r.frames += 1;
        r.fps_frames += 1;
        if time_ms - r.fps_since >= TITLE_EVERY_MS {
            r.fps = r.fps_frames as f64 * 1000.0 / (time_ms - r.fps_since);
            r.fps_frames = 0;
            r.fps_since = time_ms;
        }
        let title = title(&r.viewer, r.fps);
        if title != r.title {
            r.window.set_title(&title);
            r.title = title;
        }
        if frames.is_some_and(|n| r.frames >= n) {
            if self.setup.screenshot.is_some() {
                // The last frame again, offscreen with the same draw, and read back.
                self.save_screenshot(time_ms)?;
            }
            return Ok(true);
        }
        let p = r.viewer.params();
        let clip_playing = p.clip.is_some() && p.playing;
        if frames.is_some() || p.animate != Animation::None || clip_playing {
            r.window.request_redraw();
        }
        Ok(false)
    }

    fn save_screenshot(&mut self, time_ms: f64) -> anyhow::Result<()> {
        let path = self.screenshot_path();
        let Some(r) = self.running.as_mut() else {
            return Ok(());
        };
        let picture = capture(&r.ctx, &mut r.viewer, r.presenter.view_format(), time_ms)?;
        save(&picture, &path)?;
        eprintln!(
            "{} ({}x{})",
            path.display(),
            picture.width(),
            picture.height()
        );
        Ok(())
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, key: Key) -> anyhow::Result<()> {
        let Some(r) = self.running.as_mut() else {
            return Ok(());
        };
        let height = r.viewer.size().1;
        match view_input::key(r.viewer.params(), key, r.modifiers, height) {
            Some(Action::Set(changes)) => set(r, &changes),
            Some(Action::Quit) => event_loop.exit(),
            Some(Action::Screenshot) => {
                // A screenshot that cannot be written (a read-only folder) is reported; the
                // window stays open.
                let time_ms = r.start.elapsed().as_secs_f64() * 1000.0;
                if let Err(e) = self.save_screenshot(time_ms) {
                    eprintln!("error: {e:#}");
                }
            }
            None => {}
        }
        Ok(())
    }
}

/// Applies `changes`; a refused one (a level the device cannot draw) is reported and the view
/// stays as it was.
fn set(r: &mut Running, changes: &Map<String, Value>) {
    match r.viewer.set(changes) {
        Ok(()) => r.window.request_redraw(),
        Err(e) => eprintln!("error: {e}"),
    }
}

/// "creature.obj: pn level 8 | 20480 triangles | 60 fps".
fn title(viewer: &Viewer, fps: f64) -> String {
    let p = viewer.params();
    let s = viewer.stats();
    let schemes = p
        .schemes()
        .iter()
        .map(|s| s.name())
        .collect::<Vec<_>>()
        .join(",");
    let levels = match &p.lod {
        Some(lod) => format!("lod {lod} (level {:.1})", s.level),
        None => format!("level {}", p.level),
    };
    let clip = match &p.clip {
        Some(clip) => format!(
            " | {clip} {:.2}/{:.2} s{} | {} bytes a frame",
            p.time,
            s.duration,
            if p.playing { "" } else { " (paused)" },
            s.uploaded_bytes
        ),
        None => String::new(),
    };
    format!(
        "tessella view: {schemes} {levels} | {} triangles | {fps:.0} fps{clip}",
        s.refined_triangles
    )
}

/// A frame drawn by `viewer.draw` into a texture of its own (the window's format) and read
/// back as RGBA.
fn capture(
    ctx: &GpuContext,
    viewer: &mut Viewer,
    format: wgpu::TextureFormat,
    time_ms: f64,
) -> anyhow::Result<RgbaImage> {
    use wgpu::TextureFormat as F;
    let bgra = match format {
        F::Bgra8Unorm | F::Bgra8UnormSrgb => true,
        F::Rgba8Unorm | F::Rgba8UnormSrgb => false,
        other => anyhow::bail!("cannot save a screenshot of a window in {other:?}"),
    };
    let (width, height) = viewer.size();
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
    let texture = ctx.scoped(|| {
        tessella_view::texture(ctx, "view: screenshot", (width, height), format, 1, usage)
    })?;
    viewer.draw(&texture.create_view(&Default::default()), time_ms)?;
    let mut picture = tessella_view::read_texture(ctx, &texture)?;
    if bgra {
        for pixel in picture.pixels_mut() {
            pixel.0.swap(0, 2);
        }
    }
    Ok(picture)
}

/// Writes the PNG through a temporary file in the same folder, renamed into place.
fn save(picture: &RgbaImage, path: &Path) -> anyhow::Result<()> {
    tessella_view::save_png(picture, path)
        .with_context(|| format!("cannot write {}", path.display()))
}

fn key_of(key: &WinitKey) -> Option<Key> {
    Some(match key {
        WinitKey::Named(NamedKey::ArrowLeft) => Key::Left,
        WinitKey::Named(NamedKey::ArrowRight) => Key::Right,
        WinitKey::Named(NamedKey::ArrowUp) => Key::Up,
        WinitKey::Named(NamedKey::ArrowDown) => Key::Down,
        WinitKey::Named(NamedKey::Tab) => Key::Tab,
        WinitKey::Named(NamedKey::Escape) => Key::Escape,
        WinitKey::Named(NamedKey::Space) => Key::Char(' '),
        WinitKey::Character(text) => {
            let mut chars = text.chars();
            match (chars.next(), chars.next()) {
                (Some(c), None) => Key::Char(c.to_ascii_lowercase()),
                _ => return None,
            }
        }
        _ => return None,
    })
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(running) => self.running = Some(running),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(r) = self.running.as_mut() else {
            return;
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) if size.width > 0 && size.height > 0 => {
                let resized = r
                    .presenter
                    .resize(&r.ctx, size.width, size.height)
                    .and_then(|()| r.viewer.resize(size.width, size.height));
                match resized {
                    Ok(()) => r.window.request_redraw(),
                    Err(e) => self.fail(event_loop, e.into()),
                }
            }
            WindowEvent::RedrawRequested => match self.redraw() {
                Ok(true) => event_loop.exit(),
                Ok(false) => {}
                Err(e) => self.fail(event_loop, e),
            },
            WindowEvent::ModifiersChanged(m) => {
                r.modifiers = Modifiers {
                    shift: m.state().shift_key(),
                    alt: m.state().alt_key(),
                };
            }
            WindowEvent::KeyboardInput {
                event,
                is_synthetic,
                ..
            } if event.state == ElementState::Pressed => {
                // Shift+Tab and shifted arrows keep their keys; `+` arrives as its character.
                let key = key_of(&event.logical_key)
                    .filter(|&k| view_input::acts(k, event.repeat, is_synthetic));
                if let Some(key) = key {
                    if let Err(e) = self.key(event_loop, key) {
                        self.fail(event_loop, e);
                    }
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let i = match button {
                    MouseButton::Left => 0,
                    MouseButton::Right => 1,
                    MouseButton::Middle => 2,
                    _ => return,
                };
                r.buttons[i] = state == ElementState::Pressed;
            }
            WindowEvent::CursorMoved { position, .. } => {
                let last = r.cursor.replace((position.x, position.y));
                let Some((x, y)) = last else { return };
                let (dx, dy) = ((position.x - x) as f32, (position.y - y) as f32);
                let changes = if r.buttons[1] || r.buttons[2] || (r.buttons[0] && r.modifiers.shift)
                {
                    view_input::pan(r.viewer.params(), dx, dy, r.viewer.size().1)
                } else if r.buttons[0] {
                    view_input::orbit(r.viewer.params(), dx, dy)
                } else {
                    return;
                };
                set(r, &changes);
            }
            WindowEvent::CursorLeft { .. } => r.cursor = None,
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 100.0,
                };
                let changes = view_input::wheel(r.viewer.params(), lines);
                set(r, &changes);
            }
            _ => {}
        }
    }
}
