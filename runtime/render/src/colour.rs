//! Colours and fill styles: fixed ones for the world, surfaces and robots, and a stable colour
//! per movable object's name, so a can keeps its colour from one picture to the next.

/// How a filled outline is painted.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Style {
    pub(crate) fill: String,
    pub(crate) stroke: String,
    /// Opacity of fill and stroke; faded copies (a trajectory's first step) are drawn lighter.
    pub(crate) opacity: f64,
    /// Dashed outlines mark faded copies, so they read as "earlier" even in grey print.
    pub(crate) dashed: bool,
    /// A thick outline in [`MARK_COLOUR`]: a body the drawing points at (one in the way).
    pub(crate) marked: bool,
}

/// What a body is, which decides its colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Role {
    /// The static world (floor, table): pale, it is only the backdrop.
    World,
    /// Static bodies that take part in relations (surfaces, boxes, counters): grey.
    Surface,
    /// Movable objects: a colour of their own.
    Movable,
    /// Robot links.
    Robot,
}

/// Opacity of a faded copy.
pub(crate) const FADED_OPACITY: f64 = 0.35;

/// The colour of the gripper path.
pub(crate) const PATH_COLOUR: &str = "#d62728";
/// The outline of a marked body: the path's red, which nothing else is filled with.
pub(crate) const MARK_COLOUR: &str = PATH_COLOUR;

/// The style of a body with this role and name.
pub(crate) fn style_for(role: Role, name: &str, faded: bool) -> Style {
    let (fill, stroke) = match role {
        Role::World => ("#efeadf".to_string(), "#b9b09c".to_string()),
        Role::Surface => ("#a9a9a9".to_string(), "#5c5c5c".to_string()),
        Role::Robot => ("#5b7fb0".to_string(), "#1f3a60".to_string()),
        Role::Movable => {
            let hue = stable_hue(name);
            (hsl_to_hex(hue, 0.62, 0.55), hsl_to_hex(hue, 0.62, 0.30))
        }
    };
    Style {
        fill,
        stroke,
        opacity: if faded { FADED_OPACITY } else { 1.0 },
        dashed: faded,
        marked: false,
    }
}

/// The colour of the `index`-th sample set of a region plot (a fixed qualitative palette).
pub(crate) fn set_colour(index: usize) -> &'static str {
    const PALETTE: [&str; 8] =
        ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"];
    PALETTE[index % PALETTE.len()]
}

/// A hue in degrees from the name's FNV-1a hash: stable across runs, platforms and releases
/// (unlike `std`'s hasher, which is seeded per process).
fn stable_hue(name: &str) -> f64 {
    let mut hash: u32 = 0x811c_9dc5;
    for byte in name.bytes() {
        hash ^= u32::from(byte);
        hash = hash.wrapping_mul(0x0100_0193);
    }
    // Multiplying by the golden ratio spreads consecutive names (`can1`, `can2`) across the wheel.
    let spread = (f64::from(hash) * 0.618_033_988_749_895).fract();
    (spread * 360.0).floor()
}

/// `#rrggbb` for a hue in degrees, saturation and lightness in [0, 1].
fn hsl_to_hex(hue: f64, saturation: f64, lightness: f64) -> String {
    let chroma = (1.0 - (2.0 * lightness - 1.0).abs()) * saturation;
    let sector = hue / 60.0;
    let x = chroma * (1.0 - (sector % 2.0 - 1.0).abs());
    let (r, g, b) = match sector as u32 {
        0 => (chroma, x, 0.0),
        1 => (x, chroma, 0.0),
        2 => (0.0, chroma, x),
        3 => (0.0, x, chroma),
        4 => (x, 0.0, chroma),
        _ => (chroma, 0.0, x),
    };
    let m = lightness - chroma / 2.0;
    let byte = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    format!("#{:02x}{:02x}{:02x}", byte(r), byte(g), byte(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_name_always_gets_the_same_colour_and_names_differ() {
        let a = style_for(Role::Movable, "can1", false);
        assert_eq!(a, style_for(Role::Movable, "can1", false));
        assert_ne!(a.fill, style_for(Role::Movable, "can2", false).fill);
        assert_eq!(stable_hue("can1"), stable_hue("can1"));
    }

    #[test]
    fn hsl_conversion_hits_the_primaries() {
        assert_eq!(hsl_to_hex(0.0, 1.0, 0.5), "#ff0000");
        assert_eq!(hsl_to_hex(120.0, 1.0, 0.5), "#00ff00");
        assert_eq!(hsl_to_hex(240.0, 1.0, 0.5), "#0000ff");
        assert_eq!(hsl_to_hex(0.0, 0.0, 1.0), "#ffffff");
    }

    #[test]
    fn faded_styles_are_lighter_and_dashed() {
        let faded = style_for(Role::Robot, "gripper", true);
        assert!(faded.dashed);
        assert!(faded.opacity < 1.0);
    }
}
