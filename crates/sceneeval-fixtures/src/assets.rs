//! The procedural furniture catalog: each asset is a few closed primitives in the **asset
//! frame** (y up, front toward +z, origin at the bottom centre of its bounds, metres), like the
//! GLB files of real asset sets.
//!
//! Sizes are realistic and the front is recognisable from the geometry: the bed's headboard,
//! the chair's backrest, the bookshelf's back panel and the desk's modesty panel sit at the back
//! (-z); the TV's screen, the painting's canvas and the handles of the nightstand, wardrobe,
//! TV stand and storage box sit at the front (+z). Every asset stays under 300 triangles.
//!
//! | id | category | width x depth x height (m) |
//! |---|---|---|
//! | `bed` | bed | 1.6 x 2.1 x 1.1 |
//! | `nightstand` | nightstand | 0.45 x 0.42 x 0.55 |
//! | `desk` | desk | 1.4 x 0.7 x 0.75 |
//! | `chair` | chair | 0.44 x 0.44 x 0.9 |
//! | `dining_table` | dining table | 1.6 x 0.9 x 0.76 |
//! | `sofa` | sofa | 2.0 x 0.9 x 0.85 |
//! | `coffee_table` | coffee table | 1.1 x 0.6 x 0.45 |
//! | `wardrobe` | wardrobe | 1.0 x 0.6 x 2.0 |
//! | `bookshelf` | bookshelf | 0.8 x 0.3 x 1.8 |
//! | `table_lamp` | table lamp | 0.24 x 0.24 x 0.45 |
//! | `floor_lamp` | floor lamp | 0.44 x 0.44 x 1.7 |
//! | `rug` | rug | 2.0 x 1.4 x 0.01 |
//! | `painting` | painting | 0.8 x 0.04 x 0.6 |
//! | `ceiling_lamp` | ceiling lamp | 0.5 x 0.5 x 0.73 |
//! | `tv` | tv | 1.2 x 0.06 x 0.7 |
//! | `plant` | plant | 0.5 x 0.5 x 0.75 |
//! | `tv_stand` | tv stand | 1.4 x 0.4 x 0.5 |
//! | `storage_box` | storage box | 0.3 x 0.25 x 0.2 |
//!
//! Width is the asset's x extent, depth its z extent (front to back) and height its y extent;
//! in the object frame these become x, y and z.

use sceneeval_io::{GlbImage, GlbMaterial, GlbMesh};

use crate::primitives::{Part, bounds_of};

/// Segments used for round parts (a multiple of 4, so radii are exact along x and z).
const ROUND: usize = 12;
/// Segments used for thin round parts (stems, cords).
const THIN: usize = 8;

/// One procedural asset: id, metadata and parts in the asset frame.
#[derive(Debug, Clone, PartialEq)]
pub struct AssetDef {
    /// Asset id: the file stem (`<id>.glb`, `<id>.json`) and the part after `fixture.` in
    /// model ids.
    pub id: &'static str,
    /// Category written to the sidecar metadata (spaces, as a person would write it).
    pub category: &'static str,
    /// One-sentence description written to the sidecar metadata.
    pub description: &'static str,
    /// The closed parts, in the asset frame.
    pub parts: Vec<Part>,
}

impl AssetDef {
    /// The asset's bounds `(min, max)` in the asset frame.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        bounds_of(&self.parts)
    }

    /// Size `[width, height, depth]` in the asset frame (x, y, z extents).
    pub fn asset_size(&self) -> [f64; 3] {
        let (lo, hi) = self.bounds();
        [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]]
    }

    /// Total triangle count.
    pub fn triangle_count(&self) -> usize {
        self.parts.iter().map(|p| p.triangles.len()).sum()
    }

    /// The part with this name.
    pub fn part(&self, name: &str) -> Option<&Part> {
        self.parts.iter().find(|p| p.name == name)
    }

    /// The parts as GLB meshes (one node each, `f32` positions, a matte material of the
    /// part's colour from [`part_color`]), for `sceneeval_io::write_glb`. The painting's canvas
    /// carries an embedded PNG landscape ([`landscape_png`]) mapped onto its front.
    pub fn glb_meshes(&self) -> Vec<GlbMesh> {
        self.parts
            .iter()
            .map(|p| {
                let mesh = GlbMesh::new(
                    p.name.clone(),
                    // Narrowing to f32 is the point: glTF stores f32 positions.
                    p.positions.iter().map(|q| q.map(|c| c as f32)).collect(),
                    p.triangles.iter().flatten().copied().collect(),
                );
                let material = GlbMaterial::color(part_color(self.id, &p.name));
                if (self.id, p.name.as_str()) == ("painting", "canvas") {
                    // The picture spans the canvas's x (u) and y (v runs down the image).
                    let (lo, hi) = p.bounds();
                    let uvs = p
                        .positions
                        .iter()
                        .map(|q| {
                            [
                                ((q[0] - lo[0]) / (hi[0] - lo[0])) as f32,
                                (1.0 - (q[1] - lo[1]) / (hi[1] - lo[1])) as f32,
                            ]
                        })
                        .collect();
                    mesh.with_uvs(uvs)
                        .with_material(material.with_texture(GlbImage::EmbeddedPng(landscape_png())))
                } else {
                    mesh.with_material(material)
                }
            })
            .collect()
    }
}

/// Linear RGB colours of the catalog's materials.
mod palette {
    pub const WOOD: [f32; 3] = [0.40, 0.22, 0.10];
    pub const LIGHT_WOOD: [f32; 3] = [0.60, 0.42, 0.24];
    pub const DARK_WOOD: [f32; 3] = [0.22, 0.11, 0.05];
    pub const WHITE_FABRIC: [f32; 3] = [0.85, 0.85, 0.82];
    pub const PILLOW: [f32; 3] = [0.70, 0.75, 0.85];
    pub const GREY_FABRIC: [f32; 3] = [0.32, 0.33, 0.35];
    pub const BLACK: [f32; 3] = [0.03, 0.03, 0.03];
    pub const METAL: [f32; 3] = [0.55, 0.55, 0.57];
    pub const BRASS: [f32; 3] = [0.65, 0.45, 0.15];
    pub const CREAM: [f32; 3] = [0.90, 0.82, 0.62];
    pub const WARDROBE: [f32; 3] = [0.78, 0.74, 0.66];
    pub const RUG_RED: [f32; 3] = [0.50, 0.07, 0.05];
    pub const FRAME: [f32; 3] = [0.35, 0.20, 0.06];
    pub const SCREEN: [f32; 3] = [0.02, 0.03, 0.05];
    pub const TERRACOTTA: [f32; 3] = [0.55, 0.18, 0.07];
    pub const FOLIAGE: [f32; 3] = [0.07, 0.32, 0.06];
    pub const CARDBOARD: [f32; 3] = [0.55, 0.36, 0.18];
    pub const LABEL: [f32; 3] = [0.90, 0.90, 0.88];
}

/// The linear RGB base colour of part `part` of asset `asset`, chosen to match the
/// descriptions (a grey fabric sofa, a white mattress, a wooden nightstand with a metal handle,
/// a black TV frame, ...).
pub fn part_color(asset: &str, part: &str) -> [f32; 3] {
    use palette::*;
    match (asset, part) {
        ("bed", "mattress") => WHITE_FABRIC,
        ("bed", p) if p.starts_with("pillow") => PILLOW,
        ("bed" | "nightstand" | "chair", _) => {
            if part == "handle" {
                METAL
            } else {
                WOOD
            }
        }
        ("desk" | "coffee_table" | "bookshelf", _) => LIGHT_WOOD,
        ("dining_table", _) => DARK_WOOD,
        ("sofa", p) if p.starts_with("leg") => BLACK,
        ("sofa", _) => GREY_FABRIC,
        ("wardrobe" | "tv_stand", p) if p.starts_with("handle") => METAL,
        ("wardrobe", _) => WARDROBE,
        ("tv_stand", _) => DARK_WOOD,
        ("table_lamp", "shade") => CREAM,
        ("table_lamp", _) => BRASS,
        ("floor_lamp", "shade") | ("ceiling_lamp", "shade" | "canopy") => WHITE_FABRIC,
        ("floor_lamp" | "ceiling_lamp", _) => BLACK,
        ("rug", _) => RUG_RED,
        ("painting", "canvas") => [1.0, 1.0, 1.0],
        ("painting", _) => FRAME,
        ("tv", "screen") => SCREEN,
        ("tv", _) => BLACK,
        ("plant", "pot") => TERRACOTTA,
        ("plant", _) => FOLIAGE,
        ("storage_box", "label") => LABEL,
        ("storage_box", _) => CARDBOARD,
        _ => [0.8, 0.8, 0.8],
    }
}

/// The painting's picture: a 32 x 24 PNG of a blue sky with a yellow sun over green hills,
/// drawn by code (byte-identical on every run).
pub fn landscape_png() -> Vec<u8> {
    let (w, h) = (32u32, 24u32);
    let mut rgba = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            let (fx, fy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
            let horizon = 14.0 + 2.5 * (fx * 0.35).sin();
            let sun = (fx - 23.0).powi(2) + (fy - 6.0).powi(2) < 12.0;
            let px: [u8; 4] = if fy > horizon {
                // Hills, darker towards the bottom.
                let shade = (fy - horizon) / (f64::from(h) - horizon);
                [(70.0 - 30.0 * shade) as u8, (150.0 - 50.0 * shade) as u8, 50, 255]
            } else if sun {
                [250, 215, 60, 255]
            } else {
                // Sky, lighter towards the horizon.
                let t = fy / horizon;
                [(90.0 + 80.0 * t) as u8, (150.0 + 60.0 * t) as u8, 230, 255]
            };
            rgba.extend_from_slice(&px);
        }
    }
    let mut png = Vec::new();
    // Encoding an in-memory image of the right size cannot fail; an empty result would make
    // the canvas fall back to its white base colour.
    if let Some(image) = image::RgbaImage::from_raw(w, h, rgba) {
        let _ = image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png);
    }
    png
}

/// A box part from x, y and z ranges (asset frame: y up, +z front).
fn bx(name: &str, x: [f64; 2], y: [f64; 2], z: [f64; 2]) -> Part {
    Part::cuboid(name, [x[0], y[0], z[0]], [x[1], y[1], z[1]])
}

/// Four box legs of square section `s`, at x = +-`x` and z = +-`z` (outer faces), from the
/// floor to `top`.
fn legs(x: f64, z: f64, s: f64, top: f64) -> Vec<Part> {
    let mut out = Vec::with_capacity(4);
    for (i, (sx, sz)) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
        .into_iter()
        .enumerate()
    {
        let xr = if sx < 0.0 { [-x, -x + s] } else { [x - s, x] };
        let zr = if sz < 0.0 { [-z, -z + s] } else { [z - s, z] };
        out.push(bx(&format!("leg_{i}"), xr, [0.0, top], zr));
    }
    out
}

fn bed() -> AssetDef {
    let mut parts = legs(0.78, 1.03, 0.06, 0.25);
    parts.extend([
        bx("frame", [-0.8, 0.8], [0.25, 0.35], [-0.97, 1.05]),
        bx("mattress", [-0.78, 0.78], [0.35, 0.55], [-0.95, 1.03]),
        bx("pillow_0", [-0.7, -0.05], [0.55, 0.67], [-0.93, -0.55]),
        bx("pillow_1", [0.05, 0.7], [0.55, 0.67], [-0.93, -0.55]),
        // The headboard stands on the floor at the back (-z).
        bx("headboard", [-0.8, 0.8], [0.0, 1.1], [-1.05, -0.97]),
    ]);
    AssetDef {
        id: "bed",
        category: "bed",
        description: "A double bed with a tall headboard, a white mattress and two pillows.",
        parts,
    }
}

fn nightstand() -> AssetDef {
    AssetDef {
        id: "nightstand",
        category: "nightstand",
        description: "A small wooden nightstand with one drawer and a metal handle.",
        parts: vec![
            bx("carcass", [-0.225, 0.225], [0.0, 0.55], [-0.21, 0.19]),
            bx("handle", [-0.06, 0.06], [0.42, 0.45], [0.19, 0.21]),
        ],
    }
}

fn desk() -> AssetDef {
    let mut parts = legs(0.68, 0.33, 0.04, 0.72);
    parts.extend([
        bx("top", [-0.7, 0.7], [0.72, 0.75], [-0.35, 0.35]),
        // The modesty panel closes the back (-z); the user sits at the open front.
        bx("modesty_panel", [-0.64, 0.64], [0.35, 0.72], [-0.32, -0.3]),
    ]);
    AssetDef {
        id: "desk",
        category: "desk",
        description: "A rectangular office desk with four legs and a modesty panel at the back.",
        parts,
    }
}

fn chair() -> AssetDef {
    let mut parts = legs(0.21, 0.21, 0.03, 0.42);
    parts.extend([
        bx("seat", [-0.22, 0.22], [0.42, 0.46], [-0.22, 0.22]),
        bx("backrest", [-0.22, 0.22], [0.46, 0.9], [-0.22, -0.19]),
    ]);
    AssetDef {
        id: "chair",
        category: "chair",
        description: "A simple wooden chair with four legs and a straight backrest.",
        parts,
    }
}

fn dining_table() -> AssetDef {
    let mut parts = legs(0.74, 0.39, 0.06, 0.72);
    parts.push(bx("top", [-0.8, 0.8], [0.72, 0.76], [-0.45, 0.45]));
    AssetDef {
        id: "dining_table",
        category: "dining table",
        description: "A rectangular wooden dining table for six people.",
        parts,
    }
}

fn sofa() -> AssetDef {
    let mut parts = legs(0.95, 0.4, 0.05, 0.1);
    parts.extend([
        bx("base", [-1.0, 1.0], [0.1, 0.42], [-0.45, 0.45]),
        bx("backrest", [-1.0, 1.0], [0.42, 0.85], [-0.45, -0.25]),
        bx("arm_0", [-1.0, -0.85], [0.42, 0.62], [-0.25, 0.45]),
        bx("arm_1", [0.85, 1.0], [0.42, 0.62], [-0.25, 0.45]),
        bx("cushion_0", [-0.84, -0.01], [0.42, 0.5], [-0.25, 0.43]),
        bx("cushion_1", [0.01, 0.84], [0.42, 0.5], [-0.25, 0.43]),
    ]);
    AssetDef {
        id: "sofa",
        category: "sofa",
        description: "A grey three-seat fabric sofa with armrests and two seat cushions.",
        parts,
    }
}

fn coffee_table() -> AssetDef {
    let mut parts = legs(0.52, 0.27, 0.05, 0.41);
    parts.extend([
        bx("top", [-0.55, 0.55], [0.41, 0.45], [-0.3, 0.3]),
        bx("shelf", [-0.47, 0.47], [0.12, 0.14], [-0.22, 0.22]),
    ]);
    AssetDef {
        id: "coffee_table",
        category: "coffee table",
        description: "A low rectangular coffee table with a lower shelf.",
        parts,
    }
}

fn wardrobe() -> AssetDef {
    AssetDef {
        id: "wardrobe",
        category: "wardrobe",
        description: "A tall two-door wardrobe with vertical handles.",
        parts: vec![
            // A closed solid box, so that an object placed inside it is fully enclosed.
            bx("carcass", [-0.5, 0.5], [0.0, 2.0], [-0.3, 0.28]),
            bx("handle_0", [-0.06, -0.04], [0.9, 1.2], [0.28, 0.3]),
            bx("handle_1", [0.04, 0.06], [0.9, 1.2], [0.28, 0.3]),
        ],
    }
}

fn bookshelf() -> AssetDef {
    let mut parts = vec![
        bx("side_0", [-0.4, -0.38], [0.0, 1.8], [-0.15, 0.15]),
        bx("side_1", [0.38, 0.4], [0.0, 1.8], [-0.15, 0.15]),
        bx("bottom", [-0.38, 0.38], [0.0, 0.05], [-0.14, 0.15]),
        bx("top", [-0.38, 0.38], [1.78, 1.8], [-0.14, 0.15]),
        // The back panel closes the back (-z); the shelves open to the front.
        bx("back", [-0.38, 0.38], [0.0, 1.8], [-0.15, -0.14]),
    ];
    for (i, y) in [0.5, 0.95, 1.4].into_iter().enumerate() {
        parts.push(bx(
            &format!("shelf_{i}"),
            [-0.38, 0.38],
            [y, y + 0.02],
            [-0.14, 0.15],
        ));
    }
    AssetDef {
        id: "bookshelf",
        category: "bookshelf",
        description: "A tall open bookshelf with four shelves and a back panel.",
        parts,
    }
}

fn table_lamp() -> AssetDef {
    AssetDef {
        id: "table_lamp",
        category: "table lamp",
        description: "A small table lamp with a round base and a fabric shade.",
        parts: vec![
            Part::frustum("base", [0.0, 0.0, 0.0], 0.03, 0.08, 0.08, ROUND),
            Part::frustum("stem", [0.0, 0.03, 0.0], 0.27, 0.01, 0.01, THIN),
            Part::frustum("shade", [0.0, 0.28, 0.0], 0.17, 0.12, 0.08, ROUND),
        ],
    }
}

fn floor_lamp() -> AssetDef {
    AssetDef {
        id: "floor_lamp",
        category: "floor lamp",
        description: "A standing floor lamp with a heavy round base, a thin pole and a wide shade.",
        parts: vec![
            Part::frustum("base", [0.0, 0.0, 0.0], 0.03, 0.15, 0.15, ROUND),
            Part::frustum("pole", [0.0, 0.03, 0.0], 1.42, 0.015, 0.015, THIN),
            Part::frustum("shade", [0.0, 1.4, 0.0], 0.3, 0.22, 0.15, ROUND),
        ],
    }
}

fn rug() -> AssetDef {
    AssetDef {
        id: "rug",
        category: "rug",
        description: "A rectangular woven rug, one centimetre thick.",
        parts: vec![bx("rug", [-1.0, 1.0], [0.0, 0.01], [-0.7, 0.7])],
    }
}

fn painting() -> AssetDef {
    AssetDef {
        id: "painting",
        category: "painting",
        description: "A framed landscape painting meant to hang on a wall.",
        parts: vec![
            bx("frame", [-0.4, 0.4], [0.0, 0.6], [-0.02, 0.01]),
            // The canvas faces the room (+z).
            bx("canvas", [-0.36, 0.36], [0.04, 0.56], [0.01, 0.02]),
        ],
    }
}

fn ceiling_lamp() -> AssetDef {
    AssetDef {
        id: "ceiling_lamp",
        category: "ceiling lamp",
        description: "A pendant ceiling lamp: a wide shade hanging from a cord and a ceiling canopy.",
        parts: vec![
            Part::frustum("shade", [0.0, 0.0, 0.0], 0.2, 0.25, 0.1, ROUND),
            Part::frustum("cord", [0.0, 0.2, 0.0], 0.5, 0.006, 0.006, THIN),
            // The canopy's top face is the mounting point on the ceiling.
            Part::frustum("canopy", [0.0, 0.7, 0.0], 0.03, 0.06, 0.06, ROUND),
        ],
    }
}

fn tv() -> AssetDef {
    AssetDef {
        id: "tv",
        category: "tv",
        description: "A flat-screen television with a thin black frame.",
        parts: vec![
            bx("back_housing", [-0.3, 0.3], [0.15, 0.55], [-0.03, -0.015]),
            bx("panel", [-0.6, 0.6], [0.0, 0.7], [-0.015, 0.02]),
            // The screen faces the viewer (+z).
            bx("screen", [-0.58, 0.58], [0.02, 0.68], [0.02, 0.03]),
        ],
    }
}

fn plant() -> AssetDef {
    AssetDef {
        id: "plant",
        category: "plant",
        description: "A leafy potted plant in a round ceramic pot.",
        parts: vec![
            Part::frustum("pot", [0.0, 0.0, 0.0], 0.3, 0.12, 0.15, ROUND),
            Part::sphere("foliage", [0.0, 0.5, 0.0], 0.25, ROUND, 6),
        ],
    }
}

fn tv_stand() -> AssetDef {
    AssetDef {
        id: "tv_stand",
        category: "tv stand",
        description: "A low media cabinet with two drawers for a television.",
        parts: vec![
            bx("plinth", [-0.68, 0.68], [0.0, 0.05], [-0.18, 0.16]),
            bx("carcass", [-0.7, 0.7], [0.05, 0.5], [-0.2, 0.18]),
            bx("handle_0", [-0.4, -0.2], [0.4, 0.42], [0.18, 0.2]),
            bx("handle_1", [0.2, 0.4], [0.4, 0.42], [0.18, 0.2]),
        ],
    }
}

fn storage_box() -> AssetDef {
    AssetDef {
        id: "storage_box",
        category: "storage box",
        description: "A small cardboard storage box with a label on its front.",
        parts: vec![
            bx("body", [-0.15, 0.15], [0.0, 0.2], [-0.125, 0.115]),
            bx("label", [-0.05, 0.05], [0.08, 0.12], [0.115, 0.125]),
        ],
    }
}

/// Every asset of the catalog, in a fixed order.
pub fn catalog() -> Vec<AssetDef> {
    vec![
        bed(),
        nightstand(),
        desk(),
        chair(),
        dining_table(),
        sofa(),
        coffee_table(),
        wardrobe(),
        bookshelf(),
        table_lamp(),
        floor_lamp(),
        rug(),
        painting(),
        ceiling_lamp(),
        tv(),
        plant(),
        tv_stand(),
        storage_box(),
    ]
}

/// The asset with this id.
pub fn asset(id: &str) -> Option<AssetDef> {
    catalog().into_iter().find(|a| a.id == id)
}

#[cfg(test)]
mod tests {
    use super::*;

    const REQUIRED: [&str; 16] = [
        "bed",
        "nightstand",
        "desk",
        "chair",
        "dining table",
        "sofa",
        "coffee table",
        "wardrobe",
        "bookshelf",
        "table lamp",
        "floor lamp",
        "rug",
        "painting",
        "ceiling lamp",
        "tv",
        "plant",
    ];

    #[test]
    fn catalog_covers_the_required_categories() {
        let cat = catalog();
        for c in REQUIRED {
            assert!(cat.iter().any(|a| a.category == c), "missing {c}");
        }
        let mut ids: Vec<_> = cat.iter().map(|a| a.id).collect();
        ids.sort_unstable();
        ids.dedup();
        assert_eq!(ids.len(), cat.len(), "asset ids are unique");
    }

    #[test]
    fn every_asset_has_its_origin_at_the_bottom_centre() {
        for a in catalog() {
            let (lo, hi) = a.bounds();
            assert_eq!(lo[1], 0.0, "{}: bottom at y = 0", a.id);
            assert!((lo[0] + hi[0]).abs() < 1e-12, "{}: centred in x", a.id);
            assert!((lo[2] + hi[2]).abs() < 1e-12, "{}: centred in z", a.id);
        }
    }

    #[test]
    fn every_part_is_closed_and_outward_and_assets_are_small() {
        for a in catalog() {
            assert!(
                a.triangle_count() < 300,
                "{}: {} triangles",
                a.id,
                a.triangle_count()
            );
            for p in &a.parts {
                assert!(p.signed_volume() > 0.0, "{}/{}", a.id, p.name);
            }
        }
    }

    #[test]
    fn sizes_match_the_table_in_the_module_docs() {
        // [width (x), height (y), depth (z)] in the asset frame.
        let expected: [(&str, [f64; 3]); 18] = [
            ("bed", [1.6, 1.1, 2.1]),
            ("nightstand", [0.45, 0.55, 0.42]),
            ("desk", [1.4, 0.75, 0.7]),
            ("chair", [0.44, 0.9, 0.44]),
            ("dining_table", [1.6, 0.76, 0.9]),
            ("sofa", [2.0, 0.85, 0.9]),
            ("coffee_table", [1.1, 0.45, 0.6]),
            ("wardrobe", [1.0, 2.0, 0.6]),
            ("bookshelf", [0.8, 1.8, 0.3]),
            ("table_lamp", [0.24, 0.45, 0.24]),
            ("floor_lamp", [0.44, 1.7, 0.44]),
            ("rug", [2.0, 0.01, 1.4]),
            ("painting", [0.8, 0.6, 0.04]),
            ("ceiling_lamp", [0.5, 0.73, 0.5]),
            ("tv", [1.2, 0.7, 0.06]),
            ("plant", [0.5, 0.75, 0.5]),
            ("tv_stand", [1.4, 0.5, 0.4]),
            ("storage_box", [0.3, 0.2, 0.25]),
        ];
        for (id, size) in expected {
            let a = asset(id).unwrap();
            let s = a.asset_size();
            for i in 0..3 {
                assert!(
                    (s[i] - size[i]).abs() < 1e-12,
                    "{id} axis {i}: {} vs {}",
                    s[i],
                    size[i]
                );
            }
        }
    }

    #[test]
    fn fronts_are_recognisable() {
        // Back features lie at -z, front features at +z (asset frame).
        let back = |id: &str, part: &str| asset(id).unwrap().part(part).unwrap().bounds().1[2] < 0.0;
        let front = |id: &str, part: &str| asset(id).unwrap().part(part).unwrap().bounds().0[2] > 0.0;
        assert!(back("bed", "headboard"));
        assert!(back("chair", "backrest"));
        assert!(back("desk", "modesty_panel"));
        assert!(back("bookshelf", "back"));
        assert!(back("sofa", "backrest"));
        assert!(front("tv", "screen"));
        assert!(front("painting", "canvas"));
        assert!(front("nightstand", "handle"));
        assert!(front("wardrobe", "handle_0"));
        assert!(front("storage_box", "label"));
        // The bed's headboard is its tallest part: 1.1 m against a 0.55 m mattress top.
        let bed = asset("bed").unwrap();
        assert_eq!(bed.part("headboard").unwrap().bounds().1[1], 1.1);
        assert_eq!(bed.part("mattress").unwrap().bounds().1[1], 0.55);
    }

    #[test]
    fn every_part_has_a_colour_matching_its_description() {
        for a in catalog() {
            for p in &a.parts {
                assert_ne!(part_color(a.id, &p.name), [0.8, 0.8, 0.8], "{}/{}", a.id, p.name);
            }
        }
        assert_eq!(part_color("sofa", "cushion_0"), palette::GREY_FABRIC);
        assert_eq!(part_color("bed", "mattress"), palette::WHITE_FABRIC);
        assert_eq!(part_color("nightstand", "handle"), palette::METAL);
        assert_eq!(part_color("tv", "panel"), palette::BLACK);
        let meshes = asset("painting").unwrap().glb_meshes();
        let canvas = meshes.iter().find(|m| m.name == "canvas").unwrap();
        assert!(canvas.uvs.is_some());
        assert!(canvas.material.as_ref().unwrap().texture.is_some());
    }

    #[test]
    fn the_landscape_is_a_small_png_with_sky_sun_and_hills() {
        let png = landscape_png();
        let img = image::load_from_memory(&png).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (32, 24));
        // Texel (23, 6) is the sun's centre; (2, 1) sky; (2, 22) hills.
        assert_eq!(img.get_pixel(23, 6).0, [250, 215, 60, 255]);
        let sky = img.get_pixel(2, 1).0;
        assert!(sky[2] > sky[1] && sky[1] > sky[0], "{sky:?}");
        let hill = img.get_pixel(2, 22).0;
        assert!(hill[1] > hill[0] && hill[1] > hill[2], "{hill:?}");
        assert_eq!(png, landscape_png(), "deterministic");
    }

    #[test]
    fn symmetric_assets_are_mirror_symmetric_in_x() {
        // The out-of-bounds fixture relies on the sofa being its own mirror image in x.
        let sofa = asset("sofa").unwrap();
        let mut pts: Vec<[f64; 3]> = sofa.parts.iter().flat_map(|p| p.positions.clone()).collect();
        let mut mirrored: Vec<[f64; 3]> = pts.iter().map(|p| [-p[0] + 0.0, p[1], p[2]]).collect();
        let key = |p: &[f64; 3]| (p[0].to_bits() as i64, p[1].to_bits(), p[2].to_bits());
        pts.sort_by_key(key);
        mirrored.sort_by_key(key);
        assert_eq!(pts, mirrored);
    }
}
