// fogbank_volume::Dda: Amanatides–Woo traversal of a grid of cubic cells.

struct Dda {
    cell: vec3<i32>,
    step: vec3<i32>,
    n: vec3<i32>,
    origin: vec3<f32>,
    inv_d: vec3<f32>,
    t_next: vec3<f32>,
    cell_size: f32,
    t: f32,
    t_end: f32,
}

struct DdaStep {
    cell: vec3<i32>,
    t0: f32,
    t1: f32,
}

const F32_INF: f32 = 3.4028235e38;

fn dda_new(r: Ray, cell_size: f32, n: vec3<u32>, t0: f32, t1: f32) -> Dda {
    var s: Dda;
    s.n = vec3<i32>(n);
    let p = ray_at(r, t0);
    s.t_next = vec3<f32>(F32_INF);
    s.inv_d = vec3<f32>(0.0);
    s.step = vec3<i32>(0);
    for (var a = 0; a < 3; a++) {
        s.cell[a] = clamp(i32(floor(p[a] / cell_size)), 0, s.n[a] - 1);
        let d = r.d[a];
        if (d > 0.0) {
            s.step[a] = 1;
        } else if (d < 0.0) {
            s.step[a] = -1;
        }
        if (s.step[a] != 0) {
            s.inv_d[a] = 1.0 / d;
            let boundary = f32(s.cell[a] + select(0, 1, s.step[a] > 0)) * cell_size;
            s.t_next[a] = (boundary - r.o[a]) * s.inv_d[a];
        }
    }
    s.origin = r.o;
    s.cell_size = cell_size;
    s.t = t0;
    s.t_end = t1;
    return s;
}

fn dda_next(s: ptr<function, Dda>, out: ptr<function, DdaStep>) -> bool {
    if ((*s).t >= (*s).t_end) {
        return false;
    }
    let tn = (*s).t_next;
    var a = 2;
    if (tn.x < tn.y) {
        if (tn.x < tn.z) {
            a = 0;
        }
    } else if (tn.y < tn.z) {
        a = 1;
    }
    let t1 = max(min(tn[a], (*s).t_end), (*s).t);
    (*out).cell = (*s).cell;
    (*out).t0 = (*s).t;
    (*out).t1 = t1;
    (*s).t = t1;
    (*s).cell[a] += (*s).step[a];
    if ((*s).cell[a] < 0 || (*s).cell[a] >= (*s).n[a]) {
        (*s).t = (*s).t_end;
    } else {
        let boundary = f32((*s).cell[a] + select(0, 1, (*s).step[a] > 0)) * (*s).cell_size;
        (*s).t_next[a] = (boundary - (*s).origin[a]) * (*s).inv_d[a];
    }
    return true;
}
