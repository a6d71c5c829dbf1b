//! Obstacle avoidance for walking (thesis 6.3, "avoid obstacles"): a local detour beside the
//! first robot or post in the walking corridor, and a grid A* path when no detour is clear.
//! Parameters in `formations/avoidance.ron` ([`AvoidanceParams`]).

use crate::files::Field;
use arrayvec::ArrayVec;
use libero_world::Own;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Something to walk round: a robot, a goal post, the ball on the way to a kick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obstacle {
    pub at: Own,
    /// Centre distance to keep from it [m].
    pub radius: f64,
}

/// The most obstacles considered at once (22 robots, 4 posts, the ball, and spare).
pub const MAX_OBSTACLES: usize = 32;

/// Obstacles of one cycle, on the stack.
pub type Obstacles = ArrayVec<Obstacle, MAX_OBSTACLES>;

/// The grid planner's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridParams {
    /// Cell size [m].
    pub cell_m: f64,
    /// Extra clearance added to every obstacle on the grid [m].
    pub inflation_m: f64,
    /// A path is planned again after this long [s] (or when the target moves).
    pub replan_s: f64,
    /// How far beyond the box round start and target the grid reaches [m].
    pub margin_m: f64,
}

/// `formations/avoidance.ron`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AvoidanceParams {
    /// Centre distance kept from another robot [m].
    pub robot_clearance_m: f64,
    /// Centre distance kept from a goal post [m].
    pub post_clearance_m: f64,
    /// Centre distance kept from the ball while walking to the kicking place [m].
    pub ball_clearance_m: f64,
    /// Obstacles farther than this along the way are ignored for now [m].
    pub lookahead_m: f64,
    /// How far outside an obstacle's clearance a detour point lies [m].
    pub detour_margin_m: f64,
    /// Robots not seen for this long are not obstacles [s].
    pub memory_s: f64,
    /// `KickTo` walks with avoidance until this close to the ball, then the kick skill's own
    /// approach takes over [m] ...
    pub handover_m: f64,
    /// ... or already this close when no robot or post stands in the way to the ball [m]:
    /// the kick skill walks round the ball (nothing else) without the hand-over's change of
    /// pace.
    pub clear_handover_m: f64,
    /// The point `KickTo` walks to lies this far behind the ball on the kick line [m].
    pub behind_ball_m: f64,
    /// A rolling ball is walked to where it is met at this speed on its predicted path (or
    /// where it comes to rest) [m/s].
    pub meeting_speed_m_s: f64,
    pub grid: GridParams,
}

impl Default for AvoidanceParams {
    fn default() -> Self {
        Self {
            robot_clearance_m: 0.6,
            post_clearance_m: 0.35,
            ball_clearance_m: 0.35,
            lookahead_m: 3.0,
            detour_margin_m: 0.15,
            memory_s: 3.0,
            handover_m: 1.2,
            clear_handover_m: 1.2,
            behind_ball_m: 0.7,
            meeting_speed_m_s: 0.5,
            grid: GridParams {
                cell_m: 0.2,
                inflation_m: 0.1,
                replan_s: 1.0,
                margin_m: 3.0,
            },
        }
    }
}

/// Distance from `p` to the segment a–b.
fn segment_distance(p: Own, a: Own, b: Own) -> f64 {
    let ab = b - a;
    let len2 = ab.x * ab.x + ab.y * ab.y;
    if len2 < 1e-12 {
        return p.distance(a);
    }
    let t = (((p - a).x * ab.x + (p - a).y * ab.y) / len2).clamp(0.0, 1.0);
    p.distance(a + ab.scaled(t))
}

/// An obstacle the robot already stands inside only keeps it from going deeper: its radius
/// shrinks to just below the current distance, so the robot can walk out.
fn effective(obstacles: &[Obstacle], me: Own) -> Obstacles {
    obstacles
        .iter()
        .take(MAX_OBSTACLES)
        .map(|o| Obstacle {
            at: o.at,
            radius: o.radius.min(me.distance(o.at) - 0.02).max(0.0),
        })
        .collect()
}

/// Whether the straight way from `me` to `target` passes every obstacle outside its
/// clearance (one the robot already stands inside counts only with what is left of it).
pub fn way_clear(me: Own, target: Own, obstacles: &[Obstacle]) -> bool {
    clear(me, target, &effective(obstacles, me))
}

fn clear(a: Own, b: Own, obstacles: &[Obstacle]) -> bool {
    obstacles
        .iter()
        .all(|o| o.radius <= 0.0 || segment_distance(o.at, a, b) >= o.radius)
}

/// Follows a target round obstacles, remembering the grid path between cycles.
#[derive(Debug, Clone, Default)]
pub struct Planner {
    path: Vec<Own>,
    planned_at: f64,
    planned_for: Option<Own>,
    /// +1 or −1: the side the last detour went round, kept unless the other is much shorter.
    detour_side: f64,
    grid: GridSearch,
}

impl Planner {
    /// Room for the largest plan `params` can make on `field`, so that planning during play
    /// never allocates (and the path for a plan's waypoints).
    pub fn reserve(&mut self, params: &AvoidanceParams, field: &Field) {
        let cells = self.grid.reserve(params, field);
        self.path.reserve(cells.min(4096));
    }

    /// Where to walk this cycle on the way from `me` to `target`.
    pub fn next_waypoint(
        &mut self,
        params: &AvoidanceParams,
        field: &Field,
        me: Own,
        target: Own,
        obstacles: &[Obstacle],
        now: f64,
    ) -> Own {
        let near: Obstacles = effective(obstacles, me)
            .into_iter()
            .filter(|o| {
                o.radius > 0.0
                    && me.distance(o.at) - o.radius <= params.lookahead_m
                    && target.distance(o.at) > 1e-6
            })
            .collect();
        if clear(me, target, &near) {
            self.path.clear();
            return target;
        }
        let same_target = self.planned_for.is_some_and(|t| t.distance(target) <= 0.3);
        // A grid path once taken is kept (and replanned) until the straight way is clear:
        // switching back to detours beside the first obstacle can lead into the same dead end.
        if self.path.is_empty() || !same_target {
            if let Some(w) = self.detour(params, me, target, &near) {
                self.path.clear();
                return w;
            }
        }
        if self.path.is_empty() || !same_target || now - self.planned_at > params.grid.replan_s {
            let all = effective(obstacles, me);
            if !self
                .grid
                .plan(params, field, me, target, &all, &mut self.path)
            {
                self.path.clear();
            }
            self.planned_at = now;
            self.planned_for = Some(target);
        }
        // The furthest point of the path still in clear view (string pulling).
        self.path
            .iter()
            .rev()
            .find(|p| clear(me, **p, &near))
            .copied()
            .unwrap_or(target)
    }

    /// A point beside the first obstacle in the corridor, on the side that makes the shorter
    /// clear way.
    fn detour(
        &mut self,
        params: &AvoidanceParams,
        me: Own,
        target: Own,
        near: &[Obstacle],
    ) -> Option<Own> {
        let way = target - me;
        let length = way.norm();
        if length < 1e-9 {
            return None;
        }
        let along = way.scaled(1.0 / length);
        let first = near
            .iter()
            .filter(|o| segment_distance(o.at, me, target) < o.radius)
            .min_by(|a, b| {
                let t = |o: &Obstacle| (o.at - me).x * along.x + (o.at - me).y * along.y;
                t(a).total_cmp(&t(b))
            })?;
        let normal = Own::new(-along.y, along.x);
        let offset = first.radius + params.detour_margin_m;
        let mut best: Option<(f64, f64, Own)> = None;
        for side in [1.0, -1.0] {
            let w = first.at + normal.scaled(side * offset);
            let inside = near
                .iter()
                .any(|o| !std::ptr::eq(o, first) && w.distance(o.at) < o.radius);
            if inside || !clear(me, w, near) {
                continue;
            }
            // Keep going round the side chosen before unless the other is clearly shorter.
            let bias = if side == self.detour_side { -0.3 } else { 0.0 };
            let cost = me.distance(w) + w.distance(target) + bias;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, side, w));
            }
        }
        let (_, side, w) = best?;
        self.detour_side = side;
        Some(w)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Open {
    cost: f64,
    cell: usize,
}

impl Eq for Open {}

impl Ord for Open {
    fn cmp(&self, other: &Self) -> Ordering {
        other.cost.total_cmp(&self.cost)
    }
}

impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// A* over a grid covering start and target with a margin (8-connected, octile heuristic);
/// cells within an obstacle's inflated clearance are blocked. `None` when no path exists.
pub fn plan_path(
    params: &AvoidanceParams,
    field: &Field,
    start: Own,
    target: Own,
    obstacles: &[Obstacle],
) -> Option<Vec<Own>> {
    let mut path = Vec::new();
    GridSearch::default()
        .plan(params, field, start, target, obstacles, &mut path)
        .then_some(path)
}

/// The cell size a plan uses for `cell_m` from the file [m].
fn grid_cell_m(cell_m: f64) -> f64 {
    cell_m.max(0.05)
}

/// Cells along x and y of a grid spanning `span_x` by `span_y` [m].
fn grid_size(span_x: f64, span_y: f64, cell_m: f64) -> (usize, usize) {
    let cell = grid_cell_m(cell_m);
    let across = |span: f64| ((span / cell).ceil() as usize).max(1) + 1;
    (across(span_x), across(span_y))
}

/// A plan over more cells than this is refused (a cell size far too small for the field).
const MAX_GRID_CELLS: usize = 250_000;

/// The grid search's working memory, kept between plans: a plan runs during play, and
/// allocating the grid each time put the heap on the per-cycle path.
#[derive(Debug, Clone, Default)]
struct GridSearch {
    blocked: Vec<bool>,
    best: Vec<f64>,
    came_from: Vec<usize>,
    open: BinaryHeap<Open>,
}

impl GridSearch {
    /// Room for a grid over the whole field and its border; returns its number of cells.
    fn reserve(&mut self, params: &AvoidanceParams, field: &Field) -> usize {
        let border = field.geometry().border;
        let (hx, hy) = (field.half_length() + border, field.half_width() + border);
        let (nx, ny) = grid_size(2.0 * hx, 2.0 * hy, params.grid.cell_m);
        let cells = (nx * ny).min(MAX_GRID_CELLS);
        let more = |len: usize| cells.saturating_sub(len);
        self.blocked.reserve(more(self.blocked.len()));
        self.best.reserve(more(self.best.len()));
        self.came_from.reserve(more(self.came_from.len()));
        // Each cell enters the open list at most once per neighbour that improves it.
        self.open.reserve(more(self.open.len()) * 2);
        cells
    }

    /// As [`plan_path`], into `path`; `false` when no path exists.
    fn plan(
        &mut self,
        params: &AvoidanceParams,
        field: &Field,
        start: Own,
        target: Own,
        obstacles: &[Obstacle],
        path: &mut Vec<Own>,
    ) -> bool {
        path.clear();
        let g = &params.grid;
        let border = field.geometry().border;
        let (hx, hy) = (field.half_length() + border, field.half_width() + border);
        let lo = Own::new(
            (start.x.min(target.x) - g.margin_m).max(-hx),
            (start.y.min(target.y) - g.margin_m).max(-hy),
        );
        let hi = Own::new(
            (start.x.max(target.x) + g.margin_m).min(hx),
            (start.y.max(target.y) + g.margin_m).min(hy),
        );
        let cell = grid_cell_m(g.cell_m);
        let (nx, ny) = grid_size(hi.x - lo.x, hi.y - lo.y, g.cell_m);
        if nx * ny > MAX_GRID_CELLS {
            return false;
        }
        let centre =
            |i: usize| Own::new(lo.x + (i % nx) as f64 * cell, lo.y + (i / nx) as f64 * cell);
        let index = |p: Own| {
            let ix = (((p.x - lo.x) / cell).round().max(0.0) as usize).min(nx - 1);
            let iy = (((p.y - lo.y) / cell).round().max(0.0) as usize).min(ny - 1);
            iy * nx + ix
        };
        let (from, to) = (index(start), index(target));
        let Self {
            blocked,
            best,
            came_from,
            open,
        } = self;
        blocked.clear();
        blocked.extend((0..nx * ny).map(|i| {
            let c = centre(i);
            i != from
                && i != to
                && obstacles
                    .iter()
                    .any(|o| o.radius > 0.0 && c.distance(o.at) < o.radius + g.inflation_m)
        }));
        let heuristic = |i: usize| {
            let (dx, dy) = (
                (i % nx).abs_diff(to % nx) as f64,
                (i / nx).abs_diff(to / nx) as f64,
            );
            cell * (dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy))
        };
        best.clear();
        best.resize(nx * ny, f64::INFINITY);
        came_from.clear();
        came_from.resize(nx * ny, usize::MAX);
        open.clear();
        best[from] = 0.0;
        open.push(Open {
            cost: heuristic(from),
            cell: from,
        });
        while let Some(Open { cell: current, .. }) = open.pop() {
            if current == to {
                path.push(target);
                let mut at = came_from[current];
                while at != usize::MAX && at != from {
                    path.push(centre(at));
                    at = came_from[at];
                }
                path.reverse();
                return true;
            }
            let (cx, cy) = ((current % nx) as i64, (current / nx) as i64);
            for (dx, dy) in [
                (1, 0),
                (-1, 0),
                (0, 1),
                (0, -1),
                (1, 1),
                (1, -1),
                (-1, 1),
                (-1, -1),
            ] {
                let (x, y) = (cx + dx, cy + dy);
                if x < 0 || y < 0 || x >= nx as i64 || y >= ny as i64 {
                    continue;
                }
                let next = y as usize * nx + x as usize;
                if blocked[next] {
                    continue;
                }
                let step = if dx != 0 && dy != 0 {
                    cell * std::f64::consts::SQRT_2
                } else {
                    cell
                };
                let cost = best[current] + step;
                if cost < best[next] {
                    best[next] = cost;
                    came_from[next] = current;
                    open.push(Open {
                        cost: cost + heuristic(next),
                        cell: next,
                    });
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests;
