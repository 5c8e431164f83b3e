//! Quad-tree importance sampling of an environment map (hierarchical sample warping, McCool & Harwood 1997).
//!
//! The target density is the luminance the integrator actually sees, in solid angle. Lookups are bilinear, so a
//! texel's footprint receives light from its neighbours too (half a sun's value near the sun's edges): each texel
//! therefore weighs the exact mean of the bilinearly filtered luminance over its footprint (a 3x3 kernel: 9/16 the
//! texel, 3/32 each edge neighbour, 1/64 each corner, with the lookup's wrap/clamp rules) times its exact solid
//! angle (sin(theta) integrated for equirect, the face Jacobian integrated for cube faces). A pdf built from raw
//! texels would sample a bright texel's neighbours at the sky's rate and return huge spikes whenever it hit them.
//! One tree per image (one for equirect, six for a cube) over its texel rectangle, split at the midpoints.
//!
//! **Subdivision criterion**: a node is split into (up to) four children unless it is a single texel, or its
//! texel weights are uniform to within a factor `1 + epsilon` (the piecewise-constant leaf is then exact to that
//! factor), or it holds less than a fraction `delta` of the total weight (it is sampled so rarely that a coarse
//! density costs nothing measurable). Regions of zero weight are therefore single leaves that are never visited,
//! and a tiny very bright sun is refined down to its own texels.
//!
//! **Sampling** descends from the root choosing the left or right column with `u.x` and then the top or bottom
//! child with `u.y`, rescaling the used coordinate each time (this preserves stratification of the input
//! points), and finishes with a uniform point of the leaf's texel rectangle. **pdf** finds the leaf of a direction
//! and returns `leaf weight / total / leaf (u,v) area / Jacobian(u,v)`, so `sample` and `pdf` agree exactly.

use crate::envmap::{EnvImage, EnvLayout, EnvMap};
use crate::math::luminance;
use glam::{Vec2, Vec3A};

/// Relative non-uniformity below which a node stays a leaf.
pub const EPSILON: f64 = 0.05;
/// Weight fraction below which a node stays a leaf.
pub const DELTA: f64 = 1e-6;

#[derive(Clone, Copy, Debug)]
struct Node {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
    weight: f64,
    /// Index of the first of four children, 0 for a leaf.
    children: u32,
}

/// The quad-trees of an environment map's images, each leaf a texel rectangle of near-uniform weight (see the
/// module notes).
#[derive(Clone, Debug)]
pub struct QuadTree {
    nodes: Vec<Node>,
    /// Root node of each image and the image sizes.
    roots: Vec<(u32, u32, u32)>,
    /// Cumulative root weights, for choosing an image.
    root_cdf: Vec<f64>,
    total: f64,
}

/// A sampled direction (env frame) with its solid-angle pdf.
#[derive(Clone, Copy, Debug)]
pub struct EnvSample {
    /// Unit direction towards the environment, in the map's frame.
    pub dir: Vec3A,
    /// Solid-angle density of `dir`.
    pub pdf: f32,
}

impl QuadTree {
    /// Build over `map`; `None` when the map is black.
    pub fn build(map: &EnvMap) -> Option<QuadTree> {
        let weights: Vec<Vec<f64>> = map
            .images
            .iter()
            .enumerate()
            .map(|(k, img)| {
                let filtered = filtered_luminance(img, map.layout);
                let mut w = Vec::with_capacity(img.texels.len());
                for y in 0..img.height {
                    for x in 0..img.width {
                        w.push(filtered[(y * img.width + x) as usize] * map.texel_solid_angle(k, x, y) as f64);
                    }
                }
                w
            })
            .collect();
        let total: f64 = weights.iter().flatten().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let mut tree = QuadTree { nodes: vec![], roots: vec![], root_cdf: vec![], total };
        let mut acc = 0.0;
        for (k, img) in map.images.iter().enumerate() {
            let root = tree.nodes.len() as u32;
            tree.nodes.push(Node { x0: 0, y0: 0, x1: img.width, y1: img.height, weight: 0.0, children: 0 });
            let (sum, _, _) = tree.build_node(root as usize, &weights[k], img.width);
            acc += sum;
            tree.roots.push((root, img.width, img.height));
            tree.root_cdf.push(acc);
        }
        Some(tree)
    }

    /// Build node `i` (already pushed with its rectangle); returns (sum, min, max) of its texel weights.
    fn build_node(&mut self, i: usize, w: &[f64], width: u32) -> (f64, f64, f64) {
        let Node { x0, y0, x1, y1, .. } = self.nodes[i];
        if x1 - x0 == 1 && y1 - y0 == 1 {
            let v = w[(y0 * width + x0) as usize];
            self.nodes[i].weight = v;
            return (v, v, v);
        }
        let (xm, ym) = (if x1 - x0 > 1 { (x0 + x1) / 2 } else { x1 }, if y1 - y0 > 1 { (y0 + y1) / 2 } else { y1 });
        let first = self.nodes.len();
        // Children: top-left, top-right, bottom-left, bottom-right (possibly empty rectangles).
        for (a, b, c, d) in [(x0, y0, xm, ym), (xm, y0, x1, ym), (x0, ym, xm, y1), (xm, ym, x1, y1)] {
            self.nodes.push(Node { x0: a, y0: b, x1: c, y1: d, weight: 0.0, children: 0 });
        }
        let (mut sum, mut lo, mut hi) = (0.0, f64::INFINITY, 0.0f64);
        for c in first..first + 4 {
            let n = self.nodes[c];
            if n.x0 == n.x1 || n.y0 == n.y1 {
                continue;
            }
            let (s, l, h) = self.build_node(c, w, width);
            sum += s;
            lo = lo.min(l);
            hi = hi.max(h);
        }
        self.nodes[i].weight = sum;
        let uniform = hi <= (1.0 + EPSILON) * lo;
        let negligible = sum < DELTA * self.total;
        if uniform || negligible {
            self.nodes.truncate(first);
        } else {
            self.nodes[i].children = first as u32;
        }
        (sum, lo, hi)
    }

    /// Nodes kept, over every image's tree.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Leaves of non-zero weight (those sampling can reach).
    pub fn leaf_count(&self) -> usize {
        self.nodes.iter().filter(|n| n.children == 0 && n.weight > 0.0).count()
    }

    /// Sample a direction in the map's frame.
    pub fn sample(&self, map: &EnvMap, mut u: Vec2) -> Option<EnvSample> {
        // Choose the image (reusing u.x).
        let target = u.x as f64 * self.total;
        let k = self.root_cdf.partition_point(|&c| c <= target).min(self.roots.len() - 1);
        let lo = if k == 0 { 0.0 } else { self.root_cdf[k - 1] };
        let span = self.root_cdf[k] - lo;
        if span <= 0.0 {
            return None;
        }
        u.x = (((target - lo) / span) as f32).clamp(0.0, 1.0 - f32::EPSILON);
        let (root, w, h) = self.roots[k];
        let mut node = &self.nodes[root as usize];
        while node.children != 0 {
            let c = &self.nodes[node.children as usize..node.children as usize + 4];
            let left = c[0].weight + c[2].weight;
            let right = c[1].weight + c[3].weight;
            let p_left = left / (left + right);
            // Rounding can never send the walk into an empty column.
            let col = if right <= 0.0 || ((u.x as f64) < p_left && left > 0.0) {
                u.x = (u.x as f64 / p_left) as f32;
                0
            } else {
                u.x = ((u.x as f64 - p_left) / (1.0 - p_left)) as f32;
                1
            };
            let (top, bottom) = (c[col].weight, c[col + 2].weight);
            let p_top = top / (top + bottom);
            let row = if bottom <= 0.0 || ((u.y as f64) < p_top && top > 0.0) {
                u.y = (u.y as f64 / p_top) as f32;
                0
            } else {
                u.y = ((u.y as f64 - p_top) / (1.0 - p_top)) as f32;
                1
            };
            u = u.clamp(Vec2::ZERO, Vec2::splat(1.0 - f32::EPSILON));
            node = &c[2 * row + col];
        }
        if node.weight <= 0.0 {
            return None;
        }
        let uv = Vec2::new(
            (node.x0 as f32 + u.x * (node.x1 - node.x0) as f32) / w as f32,
            (node.y0 as f32 + u.y * (node.y1 - node.y0) as f32) / h as f32,
        );
        let pdf = self.leaf_pdf(node, w, h, map.jacobian(uv));
        (pdf > 0.0 && pdf.is_finite()).then(|| EnvSample { dir: map.direction(k, uv), pdf })
    }

    #[inline]
    fn leaf_pdf(&self, n: &Node, w: u32, h: u32, jacobian: f32) -> f32 {
        let area_uv = ((n.x1 - n.x0) as f64 * (n.y1 - n.y0) as f64) / (w as f64 * h as f64);
        ((n.weight / self.total / area_uv) / jacobian as f64) as f32
    }

    /// The leaf holding a direction (map frame), with its image size and (u, v).
    fn leaf(&self, map: &EnvMap, dir: Vec3A) -> (&Node, u32, u32, Vec2) {
        let (k, uv) = map.coords(dir);
        let (root, w, h) = self.roots[k];
        let x = ((uv.x * w as f32) as u32).min(w - 1);
        let y = ((uv.y * h as f32) as u32).min(h - 1);
        let mut node = &self.nodes[root as usize];
        while node.children != 0 {
            let c = &self.nodes[node.children as usize..node.children as usize + 4];
            let col = (x >= c[1].x0 && c[1].x0 < c[1].x1) as usize;
            let row = (y >= c[2].y0 && c[2].y0 < c[2].y1) as usize;
            node = &c[2 * row + col];
        }
        (node, w, h, uv)
    }

    /// Number of texels of the leaf holding a direction (map frame).
    pub fn leaf_texels(&self, map: &EnvMap, dir: Vec3A) -> u32 {
        let (n, ..) = self.leaf(map, dir);
        (n.x1 - n.x0) * (n.y1 - n.y0)
    }

    /// Solid-angle pdf of a direction in the map's frame.
    pub fn pdf(&self, map: &EnvMap, dir: Vec3A) -> f32 {
        let (node, w, h, uv) = self.leaf(map, dir);
        if node.weight <= 0.0 {
            return 0.0;
        }
        let j = map.jacobian(uv);
        if j <= 0.0 { 0.0 } else { self.leaf_pdf(node, w, h, j) }
    }
}

/// Mean over each texel's footprint of the bilinearly interpolated luminance (the lookup's own filter): the 3x3
/// kernel (1, 6, 1; 6, 36, 6; 1, 6, 1) / 64, with the lookup's own rule past the edges.
fn filtered_luminance(img: &EnvImage, layout: EnvLayout) -> Vec<f64> {
    let (w, h) = (img.width as i64, img.height as i64);
    let lum: Vec<f64> = img.texels.iter().map(|t| luminance(*t).max(0.0) as f64).collect();
    let at = |x: i64, y: i64| lum[layout.texel_index(x, y, w, h)];
    let mut out = Vec::with_capacity(lum.len());
    for y in 0..h {
        for x in 0..w {
            let centre = at(x, y);
            let edges = at(x - 1, y) + at(x + 1, y) + at(x, y - 1) + at(x, y + 1);
            let corners = at(x - 1, y - 1) + at(x + 1, y - 1) + at(x - 1, y + 1) + at(x + 1, y + 1);
            out.push((36.0 * centre + 6.0 * edges + corners) / 64.0);
        }
    }
    out
}
