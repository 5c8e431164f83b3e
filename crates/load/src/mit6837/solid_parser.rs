//! The assignment-6 materials of a `Materials` block: `Checkerboard`, `Noise`, `Marble` and `Wood`, each a
//! `Transform { ops }` (world point to texture space, composed like an object transform), two `materialIndex`
//! entries (the materials it mixes) and, except for the checkerboard, `octaves`, `frequency` and `amplitude`
//! (`Noise` takes only `octaves`). Omitted numbers default to 1.

use super::ast::{OpTxt, SolidTxt, SolidTxtKind};
use super::parser::Parser;
use prism_core::error::Result;

impl Parser<'_> {
    pub(super) fn solid_material(&mut self, kind: &str) -> Result<SolidTxt> {
        let k = match kind {
            "Checkerboard" => SolidTxtKind::Checkerboard,
            "Noise" => SolidTxtKind::Noise,
            "Marble" => SolidTxtKind::Marble,
            _ => SolidTxtKind::Wood,
        };
        self.expect("{", &format!("after {kind}"))?;
        let mut s = SolidTxt { kind: k, ops: vec![], materials: [0; 2], octaves: 1, frequency: 1.0, amplitude: 1.0 };
        let mut indices = Vec::new();
        let allowed: &[&str] = match k {
            SolidTxtKind::Checkerboard => &["Transform", "materialIndex"],
            SolidTxtKind::Noise => &["Transform", "materialIndex", "octaves"],
            _ => &["Transform", "materialIndex", "octaves", "frequency", "amplitude"],
        };
        loop {
            let t = self.token(&format!("a property or `}}` in {kind}"))?;
            if t.text == "}" {
                break;
            }
            if !allowed.contains(&t.text.as_str()) {
                return Err(self.error_at(
                    t.line,
                    t.col,
                    format!("unknown keyword `{}` in {kind} (expected {} or `}}`)", t.text, allowed.join(", ")),
                ));
            }
            match t.text.as_str() {
                "Transform" => {
                    self.expect("{", &format!("after Transform in {kind}"))?;
                    loop {
                        let op = self.token(&format!("a transformation or `}}` in the Transform of {kind}"))?;
                        if op.text == "}" {
                            break;
                        }
                        match self.transform_op(&op)? {
                            Some(m @ OpTxt::Matrix(_)) => s.ops.insert(0, m),
                            Some(o) => s.ops.push(o),
                            None => {
                                return Err(self.error_at(
                                    op.line,
                                    op.col,
                                    format!(
                                        "expected a transformation in the Transform of {kind}, found `{}`",
                                        op.text
                                    ),
                                ));
                            }
                        }
                    }
                }
                "materialIndex" => {
                    if indices.len() == 2 {
                        return Err(self.error(format!("{kind} mixes two materials: a third materialIndex")));
                    }
                    indices.push(self.int(&format!("`materialIndex` of {kind}"))?);
                }
                "octaves" => {
                    let o = self.int(&format!("`octaves` of {kind}"))?;
                    if o > 16 {
                        return Err(self.error(format!("{kind}: octaves must be at most 16, got {o}")));
                    }
                    s.octaves = o as u32;
                }
                "frequency" => s.frequency = self.float(&format!("`frequency` of {kind}"))?,
                _ => s.amplitude = self.float(&format!("`amplitude` of {kind}"))?,
            }
        }
        if indices.len() != 2 {
            return Err(self.error(format!("{kind} needs two materialIndex entries, found {}", indices.len())));
        }
        s.materials = [indices[0], indices[1]];
        Ok(s)
    }
}
