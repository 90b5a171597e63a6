//! An SVG drawing of a pattern: the coarse triangle as an equilateral triangle (P1 bottom left,
//! P2 bottom right, P3 on top, so counter-clockwise stays counter-clockwise on screen), the
//! small triangles' edges, and the points coloured by class (corner, edge, interior).

use std::fmt::Write;
use tessella_core::pattern::PointClass;
use tessella_core::tessellator::{Partitioning, ProcessedLevels, TessLevels};
use tessella_core::Pattern;

/// A pattern and, for tessellator spacings, how its levels were processed.
pub(crate) struct Built {
    pub pattern: Pattern,
    pub spacing: Option<Partitioning>,
    /// `None` for the grid or a culled patch.
    pub processed: Option<ProcessedLevels>,
    /// The levels as given (tessellator spacings).
    pub requested: Option<TessLevels>,
}

const SIZE: f64 = 800.0;
const MARGIN: f64 = 60.0;

/// Screen position of a barycentric point.
fn screen(l: [f64; 3]) -> (f64, f64) {
    let side = SIZE - 2.0 * MARGIN;
    let h = side * 3f64.sqrt() / 2.0;
    // P1 = (0, 0), P2 = (1, 0), P3 = (1/2, √3/2), y up; then flipped for SVG's y down.
    let x = l[1] + 0.5 * l[2];
    let y = l[2];
    let top = (SIZE - h) / 2.0;
    (MARGIN + x * side, top + h - y * h)
}

/// The SVG text. (Writing into a `String` only fails if a `Display` impl does.)
pub(crate) fn draw(built: &Built) -> Result<String, std::fmt::Error> {
    let p = &built.pattern;
    let mut s = String::new();
    let corners = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(screen);
    writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{SIZE}" height="{SIZE}" viewBox="0 0 {SIZE} {SIZE}" font-family="sans-serif" font-size="14">"#
    )?;
    writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#)?;
    writeln!(s, "<title>{}</title>", title(built))?;
    writeln!(s, r#"<text x="12" y="24">{}</text>"#, title(built))?;
    // The coarse triangle.
    writeln!(
        s,
        r##"<polygon points="{:.2},{:.2} {:.2},{:.2} {:.2},{:.2}" fill="#f4f6fb" stroke="#222" stroke-width="2"/>"##,
        corners[0].0, corners[0].1, corners[1].0, corners[1].1, corners[2].0, corners[2].1
    )?;
    // Small triangles, one path.
    let mut d = String::new();
    for t in &p.triangles {
        let [a, b, c] = t.map(|i| screen(p.points[i as usize]));
        write!(
            d,
            "M{:.2} {:.2}L{:.2} {:.2}L{:.2} {:.2}Z",
            a.0, a.1, b.0, b.1, c.0, c.1
        )?;
    }
    if !d.is_empty() {
        writeln!(
            s,
            r##"<path d="{d}" fill="none" stroke="#3a5a9a" stroke-width="0.8" stroke-linejoin="round"/>"##
        )?;
    }
    // Points.
    let r = (6.0 / (1.0 + (p.points.len() as f64).sqrt() / 8.0)).max(1.2);
    for (l, c) in p.points.iter().zip(&p.classes) {
        let (x, y) = screen(*l);
        let colour = match c {
            PointClass::Corner { .. } => "#111",
            PointClass::Edge { .. } => "#1f77b4",
            PointClass::Interior { .. } => "#d62728",
        };
        writeln!(
            s,
            r#"<circle cx="{x:.2}" cy="{y:.2}" r="{r:.2}" fill="{colour}"/>"#
        )?;
    }
    // Corner labels and, for the tessellator, each outer level beside its edge.
    for (k, (x, y)) in corners.iter().enumerate() {
        let dy = if k == 2 { -12.0 } else { 22.0 };
        writeln!(
            s,
            r#"<text x="{x:.2}" y="{:.2}" text-anchor="middle">P{}</text>"#,
            y + dy,
            k + 1
        )?;
    }
    if let Some(levels) = built.processed.map(|l| l.levels).or(built.requested) {
        // outer[k] lies on the edge opposite corner k: label it at the edge's midpoint, pushed
        // away from that corner.
        for k in 0..3 {
            let (a, b) = (corners[(k + 1) % 3], corners[(k + 2) % 3]);
            let mid = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
            let away = (mid.0 - corners[k].0, mid.1 - corners[k].1);
            let len = (away.0 * away.0 + away.1 * away.1).sqrt();
            let (x, y) = (
                mid.0 + away.0 / len * 28.0,
                mid.1 + away.1 / len * 28.0 + 5.0,
            );
            writeln!(
                s,
                r#"<text x="{x:.2}" y="{y:.2}" text-anchor="middle">outer[{k}] = {}</text>"#,
                levels.outer[k]
            )?;
        }
    }
    writeln!(s, "</svg>")?;
    Ok(s)
}

fn title(built: &Built) -> String {
    let p = &built.pattern;
    let counts = format!("{} points, {} triangles", p.points.len(), p.triangles.len());
    match (built.spacing, built.processed) {
        (None, _) => format!("grid, level {}: {counts}", p.level),
        (Some(s), Some(l)) => format!(
            "{} spacing, inner {} outer {:?} (as processed): {counts}",
            name(s),
            l.levels.inner,
            l.levels.outer
        ),
        (Some(s), None) => format!(
            "{} spacing: culled (an outer level is 0, negative or NaN)",
            name(s)
        ),
    }
}

fn name(s: Partitioning) -> &'static str {
    match s {
        Partitioning::Equal => "equal",
        Partitioning::FractionalOdd => "fractional-odd",
        Partitioning::FractionalEven => "fractional-even",
    }
}
