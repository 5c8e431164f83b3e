//! RON's error messages in the words of a scene file's author: unknown or missing fields and values name the field
//! and the accepted alternatives, never the schema's internal Rust type names. Shared by the scene loader and the
//! plugins' parameter parsing.

/// RON's message in the words of the file's author: unknown or missing fields and values name the field and the
/// accepted alternatives, never the schema's internal type names.
pub fn describe(code: &ron::Error) -> String {
    let list = |v: &[&str]| match v {
        [] => "none".to_string(),
        [one] => format!("`{one}`"),
        _ => {
            let quoted: Vec<String> = v.iter().map(|s| format!("`{s}`")).collect();
            format!("{} or {}", quoted[..quoted.len() - 1].join(", "), quoted[quoted.len() - 1])
        }
    };
    match code {
        ron::Error::NoSuchEnumVariant { expected, found, .. } => {
            format!("unknown value `{found}` (expected {})", list(expected))
        }
        ron::Error::NoSuchStructField { expected, found, .. } => {
            format!("unknown field `{found}` (expected {})", list(expected))
        }
        ron::Error::MissingStructField { field, .. } => format!("missing field `{field}`"),
        ron::Error::DuplicateStructField { field, .. } => format!("field `{field}` given twice"),
        ron::Error::SuggestRawIdentifier(found) => {
            format!("expected a name here, found `{}`", crate::error::printable(found))
        }
        ron::Error::ExceededRecursionLimit => format!(
            "nested too deeply (Prism reads at most {} levels of nested entities)",
            crate::limits::MAX_NESTING_DEPTH
        ),
        other => {
            let text = other.to_string();
            // Serde's word for a value in none of an untagged enum's forms: list the forms instead.
            match UNTAGGED.iter().find(|(ty, _)| text.contains(&format!("untagged enum {ty}"))) {
                Some((_, forms)) => format!("expected {forms}"),
                None => rename_types(&text),
            }
        }
    }
}

/// The schema's untagged enums, with the forms a value of each may take.
const UNTAGGED: [(&str, &str); 3] = [
    (
        "ColorDesc",
        "a colour: `(r, g, b)`, one number (a grey), `Texture(\"name\")` or `Map(texture: \"name\", scale: ...)`",
    ),
    ("ScalarDesc", "a number, `Texture(\"name\")` or `Map(texture: \"name\", channel: R, scale: ...)`"),
    ("ScaleDesc", "a scale: one number or `(x, y, z)`"),
];

fn rename_types(s: &str) -> String {
    // Serde names the schema's Rust types (`expected enum AccelDesc`); say what they are in the file instead.
    const NAMES: [(&str, &str); 30] = [
        ("SceneDesc", "the scene"),
        ("RenderDesc", "`render`"),
        ("CameraDesc", "`camera`"),
        ("EntityDesc", "an entity"),
        ("MaterialDesc", "a material"),
        ("ShapeDesc", "a shape"),
        ("LightDesc", "a light"),
        ("TransformOp", "a transform"),
        ("AccelDesc", "an accelerator (`bvh`, `kdtree`, `grid` or `brute`)"),
        ("TextureDesc", "a texture"),
        ("TextureRef", "a texture reference"),
        ("ColorDesc", "a colour"),
        ("ScalarDesc", "a number or texture"),
        ("ScaleDesc", "a scale"),
        ("Channel", "a channel (`R`, `G`, `B` or `Mean`)"),
        ("Wrap", "a wrap mode"),
        ("SourceLayout", "a layout (`Equirect`, `Cross` or `Faces`)"),
        ("SamplerKind", "a sampler"),
        ("PixelPattern", "a pixel pattern"),
        ("PixelFilter", "a pixel filter"),
        ("PhongParams", "phong's parameters"),
        ("EnvlightParams", "envlight's parameters"),
        ("PpmParams", "ppm's parameters"),
        ("DebugParams", "debug's parameters"),
        ("EnvStrategy", "an environment sampling strategy"),
        ("DebugMode", "a debug mode"),
        ("HeatCount", "a heat count"),
        ("PpmMode", "a ppm mode"),
        ("PhotonLookup", "a photon lookup"),
        ("V3", "a vector"),
    ];
    let mut out = s.to_string();
    for (ty, words) in NAMES {
        out = out.replace(&format!("`{ty}`"), words);
        for kind in ["struct", "enum"] {
            out = out.replace(&format!("{kind} {ty}"), words);
        }
    }
    out
}
