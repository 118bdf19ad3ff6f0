//! A bounding volume hierarchy over a mesh's triangles (object space): the rays' candidates for
//! entering the shell through its top.

use glam::DVec3;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// a leaf's first item in `order`, or an inner node's first child (the second follows)
    first: u32,
    /// items in a leaf; 0 for an inner node
    count: u32,
    /// the cone of the items' facing normals: a ray along a unit d with d . axis >= sin_half
    /// faces away from every item (2 where no such ray exists, or an item may be entered
    /// from any side)
    axis: DVec3,
    sin_half: f64,
}

/// Binary, split at the median of the longest axis of the centres, at most 4 items a leaf.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
    /// per node: its parent (the root's is 0)
    parent: Vec<u32>,
    /// per item: its leaf (u32::MAX for an item left out)
    leaf: Vec<u32>,
    /// per place in `order`: the item's facing normal (NaN where it has none), so that a leaf's
    /// items that the ray faces away from are not given
    facing: Vec<DVec3>,
}

impl Bvh {
    /// Over items given as boxes (lo, hi) and facings: a unit normal a ray entering the item
    /// goes against, or None where a ray may enter it along any direction. None for a box
    /// marks an item to leave out.
    pub(crate) fn new(boxes: &[Option<(DVec3, DVec3)>], facing: &[Option<DVec3>]) -> Bvh {
        let mut order: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&i| boxes[i as usize].is_some())
            .collect();
        let b = |i: u32| boxes[i as usize].expect("kept items have boxes");
        let mut nodes = vec![Node {
            lo: DVec3::ZERO,
            hi: DVec3::ZERO,
            first: 0,
            count: 0,
            axis: DVec3::ZERO,
            sin_half: 2.0,
        }];
        // (node, range of `order`)
        let mut todo = vec![(0usize, 0usize, order.len())];
        while let Some((ni, a, z)) = todo.pop() {
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            let (mut clo, mut chi) = (lo, hi);
            for &i in &order[a..z] {
                let (l, h) = b(i);
                (lo, hi) = (lo.min(l), hi.max(h));
                let c = 0.5 * (l + h);
                (clo, chi) = (clo.min(c), chi.max(c));
            }
            nodes[ni].lo = lo;
            nodes[ni].hi = hi;
            let cone: Option<Vec<DVec3>> =
                order[a..z].iter().map(|&i| facing[i as usize]).collect();
            if let Some(ns) = cone {
                let axis = ns.iter().copied().sum::<DVec3>().normalize_or_zero();
                let cos = ns.iter().map(|n| n.dot(axis)).fold(1.0f64, f64::min);
                if cos > 1e-9 && axis != DVec3::ZERO {
                    nodes[ni].axis = axis;
                    nodes[ni].sin_half = (1.0 - cos * cos).max(0.0).sqrt() + 1e-12;
                }
            }
            if z - a <= 4 {
                nodes[ni].first = a as u32;
                nodes[ni].count = (z - a) as u32;
                continue;
            }
            let ext = chi - clo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = (a + z) / 2;
            order[a..z].select_nth_unstable_by(mid - a, |&i, &j| {
                let (ci, cj) = (b(i).0 + b(i).1, b(j).0 + b(j).1);
                ci[axis].total_cmp(&cj[axis])
            });
            let first = nodes.len();
            let blank = Node {
                axis: DVec3::ZERO,
                sin_half: 2.0,
                ..nodes[ni]
            };
            nodes.push(blank);
            nodes.push(blank);
            nodes[ni].first = first as u32;
            nodes[ni].count = 0;
            todo.push((first, a, mid));
            todo.push((first + 1, mid, z));
        }
        let mut parent = vec![0u32; nodes.len()];
        let mut leaf = vec![u32::MAX; boxes.len()];
        for (ni, n) in nodes.iter().enumerate() {
            if n.count == 0 {
                parent[n.first as usize] = ni as u32;
                parent[n.first as usize + 1] = ni as u32;
            } else {
                for &i in &order[n.first as usize..(n.first + n.count) as usize] {
                    leaf[i as usize] = ni as u32;
                }
            }
        }
        let facing = order
            .iter()
            .map(|&i| facing[i as usize].unwrap_or(DVec3::NAN))
            .collect();
        Bvh {
            nodes,
            order,
            parent,
            leaf,
            facing,
        }
    }

    /// Whether `item` holds for an item of a node whose box `node` keeps (a node's box, lo and
    /// hi, that `node` refuses is left out with everything under it).
    pub(crate) fn any(
        &self,
        node: impl Fn(DVec3, DVec3) -> bool,
        mut item: impl FnMut(u32) -> bool,
    ) -> bool {
        if self.order.is_empty() {
            return false;
        }
        // depth first: at most one node a level waits, beside the two just put
        let mut stack = [0u32; 36];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = &self.nodes[stack[top] as usize];
            if !node(n.lo, n.hi) {
                continue;
            }
            if n.count > 0 {
                let items = &self.order[n.first as usize..(n.first + n.count) as usize];
                if items.iter().any(|&i| item(i)) {
                    return true;
                }
                continue;
            }
            stack[top] = n.first;
            stack[top + 1] = n.first + 1;
            top += 2;
        }
        false
    }

    /// Calls `f` with each item whose box the ray o + lam d meets for lam in [lam_min,
    /// lam_max] and which it does not face away from, nearer boxes first, until `f` returns
    /// false; `f` may lower lam_max (a hit found), and boxes beyond it are then left out.
    pub(crate) fn visit(
        &self,
        o: DVec3,
        d: DVec3,
        lam_min: f64,
        lam_max: f64,
        f: impl FnMut(u32, &mut f64) -> bool,
    ) {
        self.visit_near(None, o, d, lam_min, lam_max, f);
    }

    /// `visit` for a ray that starts in or near item `from`'s box, in another order: the boxes
    /// that hold from's leaf are not tested (the ray's start lies in them), but from's leaf's
    /// items are given first, then the items under the other child at each level up, nearer
    /// boxes first under each. It gives every item that `visit` gives, and may give others,
    /// whose boxes the ray does not meet or whose tops it faces away from.
    pub(crate) fn visit_from(
        &self,
        from: u32,
        o: DVec3,
        d: DVec3,
        lam_min: f64,
        lam_max: f64,
        f: impl FnMut(u32, &mut f64) -> bool,
    ) {
        self.visit_near(Some(from), o, d, lam_min, lam_max, f);
    }

    fn visit_near(
        &self,
        from: Option<u32>,
        o: DVec3,
        d: DVec3,
        lam_min: f64,
        lam_max: f64,
        mut f: impl FnMut(u32, &mut f64) -> bool,
    ) {
        if self.order.is_empty() {
            return;
        }
        // 1 / d, a zero component taken as 1e-300 of its sign: the slabs' parameters are then
        // never NaN, so that plain comparisons order them (a box that the ray runs along within
        // 1e-8 of a face of is kept, as with any box it may meet)
        let recip = |x: f64| {
            if x.abs() >= 1e-300 {
                1.0 / x
            } else {
                1e300f64.copysign(x)
            }
        };
        let inv = DVec3::new(recip(d.x), recip(d.y), recip(d.z));
        let du = d.normalize_or_zero();
        let (min, max) = (
            |a: f64, b: f64| if a < b { a } else { b },
            |a: f64, b: f64| if a > b { a } else { b },
        );
        // where the ray enters the node's box, if it meets it within [lam_min, lam_max]
        let meets = |n: &Node, lam_max: f64| -> Option<f64> {
            if du.dot(n.axis) >= n.sin_half {
                return None;
            }
            let t0 = (n.lo - o) * inv;
            let t1 = (n.hi - o) * inv;
            let tn = max(
                max(min(t0.x, t1.x), min(t0.y, t1.y)),
                max(min(t0.z, t1.z), lam_min),
            );
            let tf = min(
                min(max(t0.x, t1.x), max(t0.y, t1.y)),
                min(max(t0.z, t1.z), lam_max),
            );
            (!(tn > tf * (1.0 + 1e-12) + 1e-12)).then_some(tn)
        };
        let mut lam_max = lam_max;
        let from_leaf = from.and_then(|t| self.leaf.get(t as usize).copied());
        let Some(leaf) = from_leaf.filter(|&l| l != u32::MAX) else {
            if let Some(t_root) = meets(&self.nodes[0], lam_max) {
                self.descend((0, t_root), du, &meets, &mut lam_max, &mut f);
            }
            return;
        };
        let n = &self.nodes[leaf as usize];
        if du.dot(n.axis) < n.sin_half && !self.items(n, du, &mut lam_max, &mut f) {
            return;
        }
        let mut node = leaf;
        while node != 0 {
            let p = &self.nodes[self.parent[node as usize] as usize];
            let other = if p.first == node { node + 1 } else { node - 1 };
            if let Some(t) = meets(&self.nodes[other as usize], lam_max) {
                if !self.descend((other, t), du, &meets, &mut lam_max, &mut f) {
                    return;
                }
            }
            node = self.parent[node as usize];
        }
    }

    /// A leaf's items given to `f`, but those whose tops the ray along the unit `du` faces
    /// away from; false where `f` stopped.
    fn items(
        &self,
        n: &Node,
        du: DVec3,
        lam_max: &mut f64,
        f: &mut impl FnMut(u32, &mut f64) -> bool,
    ) -> bool {
        (n.first as usize..(n.first + n.count) as usize)
            .filter(|&k| !(du.dot(self.facing[k]) >= 0.0))
            .all(|k| f(self.order[k], lam_max))
    }

    /// The items under node `start` (met at lam start.1) that `meets` keeps, nearer boxes
    /// first, given to `f`; false where `f` stopped.
    fn descend(
        &self,
        start: (u32, f64),
        du: DVec3,
        meets: &impl Fn(&Node, f64) -> Option<f64>,
        lam_max: &mut f64,
        f: &mut impl FnMut(u32, &mut f64) -> bool,
    ) -> bool {
        // the tree is balanced (median splits): under 32 levels for any u32 count of items, and
        // at most one node a level waits
        let mut stack = [(0u32, 0f64); 34];
        stack[0] = start;
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (ni, tn) = stack[top];
            if tn > *lam_max * (1.0 + 1e-12) + 1e-12 {
                continue;
            }
            let n = &self.nodes[ni as usize];
            if n.count > 0 {
                if !self.items(n, du, lam_max, f) {
                    return false;
                }
                continue;
            }
            let (a, b) = (n.first, n.first + 1);
            let (ta, tb) = (
                meets(&self.nodes[a as usize], *lam_max),
                meets(&self.nodes[b as usize], *lam_max),
            );
            // the farther child waits below the nearer
            let mut kids = [(a, ta), (b, tb)];
            if let (Some(x), Some(y)) = (ta, tb) {
                if y < x {
                    kids.swap(0, 1);
                }
            }
            for (k, t) in kids.into_iter().rev() {
                if let Some(t) = t {
                    stack[top] = (k, t);
                    top += 1;
                }
            }
        }
        true
    }
}
