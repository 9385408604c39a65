// spectex layer library: the per-layer part of docs/sampling.md (sections 3-7),
// self-contained: it reads no uniform and no global; everything comes by
// argument, so that the renderer (ground.frag.glsl) and every export
// (WebGL2, GLSL 3.30, Godot, HLSL) include this same text after a prelude
// (spectex/shading/glsl.py) that defines
//   SPX_TEX_ARG(name)       a texture parameter      (GLSL: sampler2D name)
//   SPX_TEX(name)           passing it on            (GLSL: name)
//   SPX_LOD(name, uv, lod)  a sample at a given lod  (GLSL: textureLod(name, uv, lod))
//   SPX_UINT                an unsigned 32-bit int   (GLSL: uint); the stochastic
//                           tiling's functions (section 6b) are compiled only where it is defined
//   SPX_ANISO               1 to compile the anisotropic path (section 5)
// and the constants of spectex/shading/constants.py (SPX_BLEND_*, ...).
// Only vec2/vec3/vec4, float, int, SPX_UINT and functions common to
// GLSL and HLSL (floor, ceil, log2, exp, sqrt, length, dot, min, max, clamp)
// are used.

// Section 6: a ground point p (metres from the anchor) in a layer's tile
// coordinates; m = (m00, m01, m10, m11) is the layer's map, anchor its
// coordinates of the anchor point (float64 on the host, mod 2).
vec2 spectex_layer_coords(vec2 anchor, vec4 m, vec2 p) {
    return anchor + vec2(m.x * p.x + m.y * p.y, m.z * p.x + m.w * p.y);
}

// A world-space footprint vector pushed through a layer's map.
vec2 spectex_layer_deriv(vec4 m, vec2 j) {
    return vec2(m.x * j.x + m.y * j.y, m.z * j.x + m.w * j.y);
}

// Sections 3 and 5: the footprint of the derivatives dx, dy of (s, t), in
// texels of level 0 (tex_size = level-0 width, height). Returns n, the
// number of samples along the major axis d, and sets lam, the level of
// detail they are taken at: with SPX_ANISO and max_aniso > 1,
// EXT_texture_filter_anisotropic's recipe (lam = log2(Pmax / n)); otherwise
// n = 1 and lam = log2(Pmax). Sample i of n (1-based) lies at
// (i / (n + 1) - 1/2) d. The one home of the recipe in GLSL: the periodic
// and the stochastic samplers call it.
float spectex_footprint(vec2 dx, vec2 dy, vec2 tex_size, float max_aniso, out float lam, out vec2 d) {
    float px = length(dx * tex_size);
    float py = length(dy * tex_size);
    float pmax = max(px, py);
    float n = 1.0;
#if SPX_ANISO
    if (max_aniso > 1.0) {
        float pmin = min(px, py);
        float n_max = floor(max_aniso);
        n = (pmin * n_max <= pmax) ? n_max : min(ceil(pmax / pmin), n_max);
    }
#endif
    lam = log2(max(pmax / n, SPX_LOD_FLOOR));
    d = (px >= py) ? dx : dy;
    return n;
}

// Sections 3 and 5: samples at the level of detail of spectex_footprint,
// n of them along the major axis, averaged.
vec4 spectex_sample_grad(SPX_TEX_ARG(tile), vec2 st, vec2 dx, vec2 dy, vec2 tex_size, float max_aniso) {
    float lam;
    vec2 d;
    float n = spectex_footprint(dx, dy, tex_size, max_aniso, lam, d);
#if SPX_ANISO
    if (n > 1.0) {
        vec4 acc = vec4(0.0, 0.0, 0.0, 0.0);
        for (float i = 1.0; i <= n; i += 1.0) {
            acc += SPX_LOD(tile, st + (i / (n + 1.0) - 0.5) * d, lam);
        }
        return acc / n;
    }
#endif
    return SPX_LOD(tile, st, lam);
}

// Sections 3-4 for a periodic layer (SPX_TILING_PERIODIC) at a known lambda:
// the tile repeats (the texture's wrap mode is REPEAT).
vec4 spectex_sample_layer(SPX_TEX_ARG(tile), vec2 st, float lod) {
    return SPX_LOD(tile, st, lod);
}

// Section 6b: stochastic tiling (SPX_TILING_STOCHASTIC), histogram-preserving
// tiling and blending (Heitz and Neyret 2018; spectex/shading/stochastic.py is
// the CPU side and the numbers' home). Compiled where the prelude defines SPX_UINT.
#ifdef SPX_UINT

// Wellons' lowbias32 hash.
SPX_UINT spectex_hash(SPX_UINT x) {
    x ^= x >> 16u;
    x *= SPX_HASH_MUL1;
    x ^= x >> 15u;
    x *= SPX_HASH_MUL2;
    x ^= x >> 16u;
    return x;
}

// The offset that goes with a vertex's hash h (stochastic.vertex_offset): its
// 16-bit halves (h & 0xFFFF, h >> 16) pick one of snap.x x snap.y positions,
// k = (half * snap) >> 16, which lies floor(k tex_size / snap) texels of level 0
// into the tile (inv_size = 1 / tex_size). snap: the layer's snap counts, whole
// numbers (spectex/shading/tables.py, snap_counts: Layer.snap's structure periods
// per tile, or tex_size, every texel, without snapping). In unsigned integers, so
// every renderer computes the same offsets exactly; floats converted as int (a
// native conversion where the CPU has none for uint).
vec2 spectex_hash_offset(SPX_UINT h, vec2 tex_size, vec2 inv_size, vec2 snap) {
    SPX_UINT nx = SPX_UINT(int(snap.x));
    SPX_UINT ny = SPX_UINT(int(snap.y));
    SPX_UINT kx = ((h & 65535u) * nx) >> 16u;
    SPX_UINT ky = ((h >> 16u) * ny) >> 16u;
    return vec2(float(int((kx * SPX_UINT(int(tex_size.x))) / nx)),
                float(int((ky * SPX_UINT(int(tex_size.y))) / ny))) * inv_size;
}

// The random offset (tile units) of grid vertex (i, j) (uint, wrapping) under
// a layer's key: h = lowbias32(i ^ lowbias32(j ^ key)).
vec2 spectex_vertex_offset(SPX_UINT i, SPX_UINT j, SPX_UINT key, vec2 tex_size, vec2 inv_size, vec2 snap) {
    return spectex_hash_offset(spectex_hash(i ^ spectex_hash(j ^ key)), tex_size, inv_size, snap);
}

// The table row (fractional: row d1 + beta) that goes with the levels a
// sample at lambda reads (section 4), for the minification filter's code.
float spectex_lut_level(float lam, int min_filter, float q) {
    if (lam <= 0.0 || min_filter < SPX_FILTER_NEAREST_MIPMAP_NEAREST) {
        return 0.0;
    }
    if (min_filter <= SPX_FILTER_LINEAR_MIPMAP_NEAREST) {
        return (lam > 0.5) ? min(ceil(lam + 0.5) - 1.0, q) : 0.0;
    }
    return min(lam, q);
}

// The inverse tables at Gaussian values g (one per channel), at a
// (fractional) level: the nearest of the SPX_LUT_SUBROWS rows per level step
// from row `row0` and the nearest of the SPX_LUT_SIZE entries. The table
// texture is one channel (half-float values, R16F or R32F, NEAREST-filtered; stochastic.expand_lut),
// SPX_LUT_SIZE wide and 4 `rows` high: channel c's rows are the c-th quarter
// (a one-channel fetch costs llvmpipe less than an RGBA one).
vec4 spectex_lut(SPX_TEX_ARG(lut), vec4 g, float row0, float level, float rows) {
    float v = (row0 + floor(level * float(SPX_LUT_SUBROWS) + 0.5) + 0.5) / (4.0 * rows);
    vec4 u = (floor(clamp(g, 0.0, 1.0) * float(SPX_LUT_SIZE - 1) + 0.5) + 0.5) * (1.0 / float(SPX_LUT_SIZE));
    return vec4(SPX_LOD(lut, vec2(u.x, v), 0.0).x, SPX_LOD(lut, vec2(u.y, v + 0.25), 0.0).x,
                SPX_LOD(lut, vec2(u.z, v + 0.5), 0.0).x, SPX_LOD(lut, vec2(u.w, v + 0.75), 0.0).x);
}

// Channel c of the cell map's entry of level-0 texel xy (whole numbers; stochastic.cell_entry): texel
// idx = y w + x at row cell_row + idx / SPX_LUT_SIZE, entry idx mod SPX_LUT_SIZE. The texel's place in the
// tile is wrapped in floats: GLSL leaves % of a negative int undefined (llvmpipe's disagreed with the CPU's
// floor modulo wherever s or t was negative).
float spectex_cell_entry(SPX_TEX_ARG(lut), vec2 xy, vec2 tex_size, float cell_row, float lut_rows, int c) {
    vec2 m = min(max(xy - tex_size * floor(xy / tex_size), 0.0), tex_size - 1.0);
    int idx = int(m.y) * int(tex_size.x) + int(m.x);
    int row = idx / SPX_LUT_SIZE;
    float u = (float(idx - row * SPX_LUT_SIZE) + 0.5) * (1.0 / float(SPX_LUT_SIZE));
    float v = (cell_row + float(row) + 0.5) / (4.0 * lut_rows) + 0.25 * float(c);
    return SPX_LOD(lut, vec2(u, v), 0.0).x;
}

// The centre of the cell the texel under st holds (stochastic.cell_point), in the skewed grid: its
// cell map entry (dx, dy: channels 0 and 1 of the table texture from row cell_row, texel idx = y w + x
// at row cell_row + idx / SPX_LUT_SIZE, entry idx mod SPX_LUT_SIZE) gives the centre
// (xy + 1/2 + (dx, dy)) / tex_size, the same for every texel of the cell, moved into the skewed grid
// (grid: the tile -> grid map) from g, the grid point (relative to the base vertex) of the point p
// whose st this is (p's own, or p's plus a patch's offset).
vec2 spectex_cell_centre(SPX_TEX_ARG(lut), vec2 st, vec2 g, vec2 tex_size, vec4 grid, float cell_row,
                         float lut_rows) {
    vec2 xy = floor(st * tex_size);
    vec2 rel = (xy + 0.5 + vec2(spectex_cell_entry(SPX_TEX(lut), xy, tex_size, cell_row, lut_rows, 0),
                                spectex_cell_entry(SPX_TEX(lut), xy, tex_size, cell_row, lut_rows, 1))) / tex_size
        - st;
    return g + vec2(grid.x * rel.x + grid.y * rel.y, grid.z * rel.x + grid.w * rel.y);
}

// The vertex (relative to the grid's origin) nearest grid point gc within its triangle (the largest
// weight, the first of equals, as stochastic.nearest_vertex).
vec2 spectex_nearest_vertex(vec2 gc) {
    vec2 c = floor(gc);
    vec2 f = gc - c;
    // the triangle's vertices and weights as in stochastic.triangle_vertices
    bool lower = f.x + f.y < 1.0;
    vec3 w = lower ? vec3(1.0 - f.x - f.y, f.x, f.y) : vec3(f.x + f.y - 1.0, 1.0 - f.x, 1.0 - f.y);
    vec2 win = (w.x >= w.y && w.x >= w.z) ? (lower ? vec2(0.0, 0.0) : vec2(1.0, 1.0))
        : ((w.y >= w.z) ? (lower ? vec2(1.0, 0.0) : vec2(0.0, 1.0)) : (lower ? vec2(0.0, 1.0) : vec2(1.0, 0.0)));
    return c + win;
}

// How well vertex vk holds a cell centred at gc (stochastic.cell_score): its hat there, plus 1 where it is
// gc's nearest vertex.
float spectex_cell_score(vec2 gc, vec2 vk) {
    vec2 d = gc - vk;
    float hat = max(1.0 - max(abs(d.x), max(abs(d.y), abs(d.x + d.y))), 0.0);
    vec2 n = spectex_nearest_vertex(gc);
    return (n.x == vk.x && n.y == vk.y) ? hat + 1.0 : hat;
}

// The grid vertex (relative to the base vertex) whose patch a layer snapped along one axis only shows at st,
// and that patch's shift along the course in texels (stochastic.course_vertex): its courses (rows of boards,
// columns of bricks) change patch at a joint. The course's centre line is cut into segments of m grid cells
// (counted from the absolute vertex index), each shown by its first vertex's patch. An odd segment's patch
// is shifted so that one of its unit starts falls on the previous patch's first unit start in the segment,
// and takes over there (spectex_course_align); an even one's (or an odd one that cannot be aligned) from the
// least hiding of its first SPX_COURSE_TRIES unit starts in it on; before there, the previous segment's patch.
float spectex_course_at(SPX_TEX_ARG(lut), float along, float vrow, vec2 o, bool along_x, vec2 tex_size,
                        float cell_row, float lut_rows, int c) {
    vec2 q = vec2(along + o.x, vrow + o.y);
    return spectex_cell_entry(SPX_TEX(lut), along_x ? q : q.yx, tex_size, cell_row, lut_rows, c);
}

// An aligned patch change (stochastic._course_align): (j, shift), j the first unit start at or after texel
// start (before end) of the patch before (whole-texel offsets p: along, across), shift what moves the new
// patch's (o) unit start at or before j onto it, or its next one where that is the patch before's own joint
// (the course would run on unchanged); (-1, 0) where there is none.
vec2 spectex_course_align(SPX_TEX_ARG(lut), float start, float end, vec2 p, vec2 o, float vrow, bool along_x,
                          vec2 tex_size, float cell_row, float lut_rows) {
    float b = spectex_course_at(SPX_TEX(lut), start - 1.0, vrow, p, along_x, tex_size, cell_row, lut_rows, 1);
    if (b >= 0.5 * SPX_NO_JOINT) {
        return vec2(-1.0, 0.0);
    }
    float j = start - 1.0 + b;
    if (j >= end) {
        return vec2(-1.0, 0.0);
    }
    float a = spectex_course_at(SPX_TEX(lut), j, vrow, o, along_x, tex_size, cell_row, lut_rows, 0);
    if (a <= -0.5 * SPX_NO_JOINT) {
        return vec2(-1.0, 0.0);
    }
    // (whole texels wrapped as x - n floor(x / n): HLSL has no mod)
    float size = along_x ? tex_size.x : tex_size.y;
    float across = along_x ? tex_size.y : tex_size.x;
    float dy = o.y - p.y;
    float dx = o.x + a - p.x;
    if (dy - across * floor(dy / across) == 0.0 && dx - size * floor(dx / size) == 0.0) {
        // the patch before's own joint: the next unit start after j instead (none: a course of one joint)
        a = spectex_course_at(SPX_TEX(lut), j, vrow, o, along_x, tex_size, cell_row, lut_rows, 1);
        dx = o.x + a - p.x;
        if (dx - size * floor(dx / size) == 0.0) {
            return vec2(-1.0, 0.0);
        }
    }
    return vec2(j, a);
}

vec3 spectex_course_vertex(SPX_TEX_ARG(lut), vec2 st, vec2 g, SPX_UINT base_i, SPX_UINT base_j, SPX_UINT key,
                           vec2 snap, vec2 tex_size, vec4 grid, float cell_row, float lut_rows) {
    vec2 inv_size = 1.0 / tex_size;
    bool along_x = snap.y < tex_size.y;
    vec2 xy = floor(st * tex_size);
    float across = spectex_cell_entry(SPX_TEX(lut), xy, tex_size, cell_row, lut_rows, 2);
    float longest = spectex_cell_entry(SPX_TEX(lut), xy, tex_size, cell_row, lut_rows, 3);
    float size;
    float vc;
    float ul;
    float wl;
    float stp;
    float rho;
    float u;
    float height;
    float vrow;
    SPX_UINT base;
    if (along_x) {
        size = tex_size.x;
        vc = (xy.y + 0.5 + across) / tex_size.y;
        ul = g.x + grid.y * (vc - st.y);
        wl = g.y + grid.w * (vc - st.y);
        stp = grid.x;
        rho = 0.0;
        base = base_i;
        u = st.x;
        height = tex_size.y / snap.y;
        vrow = floor(vc * tex_size.y);
    } else {
        size = tex_size.y;
        vc = (xy.x + 0.5 + across) / tex_size.x;
        ul = g.y + grid.z * (vc - st.x);
        wl = g.x + grid.x * (vc - st.x);
        stp = grid.w;
        rho = grid.y / grid.w;
        base = base_j;
        u = st.y;
        height = tex_size.x / snap.x;
        vrow = floor(vc * tex_size.x);
    }
    float m = max(ceil(SPX_COURSE_SEGMENT * longest * stp / size), 1.0);
    float fu = floor(ul);
    float i0 = fu - float((base + SPX_UINT(int(fu))) % SPX_UINT(int(m)));
    float u0 = u + (i0 - ul) / stp;
    float end = (u0 + m / stp) * size;
    float start = floor(u0 * size + SPX_COURSE_ROUND);
    float j0 = floor(wl + rho * (i0 - ul) + SPX_COURSE_ROUND);
    float jp = floor(wl + rho * (i0 - m - ul) + SPX_COURSE_ROUND);
    vec2 cur = along_x ? vec2(i0, j0) : vec2(j0, i0);
    vec2 prev = along_x ? vec2(i0 - m, jp) : vec2(jp, i0 - m);
    vec2 oc = floor(spectex_vertex_offset(SPX_UINT(int(cur.x)) + base_i, SPX_UINT(int(cur.y)) + base_j, key,
                                          tex_size, inv_size, snap) * tex_size + 0.5);
    vec2 op = floor(spectex_vertex_offset(SPX_UINT(int(prev.x)) + base_i, SPX_UINT(int(prev.y)) + base_j, key,
                                          tex_size, inv_size, snap) * tex_size + 0.5);
    // (along, across) of each patch's whole-texel offset
    vec2 oa = along_x ? oc : oc.yx;
    vec2 pa = along_x ? op : op.yx;
    // the aligned change this segment reads: an odd segment's own, or an even one's patch before's; one call
    bool odd = ((base + SPX_UINT(int(i0))) / SPX_UINT(int(m))) % 2u == 1u;
    float jq = floor(wl + rho * (i0 - 2.0 * m - ul) + SPX_COURSE_ROUND);
    vec2 pp = along_x ? vec2(i0 - 2.0 * m, jq) : vec2(jq, i0 - 2.0 * m);
    vec2 or2 = floor(spectex_vertex_offset(SPX_UINT(int(pp.x)) + base_i, SPX_UINT(int(pp.y)) + base_j, key,
                                           tex_size, inv_size, snap) * tex_size + 0.5);
    vec2 ra = along_x ? or2 : or2.yx;
    float before = floor((u0 - m / stp) * size + SPX_COURSE_ROUND);
    vec2 js = spectex_course_align(SPX_TEX(lut), odd ? start : before, odd ? end : start, odd ? pa : ra,
                                   odd ? oa : pa, vrow, along_x, tex_size, cell_row, lut_rows);
    if (odd && js.x >= 0.0) {
        return (u * size >= js.x) ? vec3(cur, js.y) : vec3(prev, 0.0);
    }
    float prev_shift = (!odd && js.x >= 0.0) ? js.y : 0.0;
    pa.x += prev_shift;
    float cut = u0 * size;
    float best = 1.0e30;
    float pos = start;
    for (int k = 0; k < SPX_COURSE_TRIES; k++) {
        float b = spectex_course_at(SPX_TEX(lut), pos, vrow, oa, along_x, tex_size, cell_row, lut_rows, 1);
        if (b >= 0.5 * SPX_NO_JOINT || pos + b >= end) {
            break;
        }
        pos += b;
        float a = spectex_course_at(SPX_TEX(lut), pos - 1.0, vrow, pa, along_x, tex_size, cell_row, lut_rows, 0);
        float hidden = spectex_course_at(SPX_TEX(lut), pos - 1.0, vrow, pa, along_x, tex_size, cell_row, lut_rows,
                                         1) - 1.0;
        if (hidden > 0.0 && 1.0 - a < SPX_COURSE_SLIVER * height) {
            hidden += size;  // a sliver of a board: only where nothing better
        }
        if (hidden < best) {
            best = hidden;
            cut = pos;
        }
    }
    return (u * size >= cut) ? vec3(cur, 0.0) : vec3(prev, prev_shift);
}

// Where a wall of courses of their own heights starts its band's courses (stochastic.course_band_shift):
// the shift of st across the courses (tile units; 0 for any other layer). A layer snapped along one axis
// with one period across (snap.y == 1, free along x: courses along x; or snap.x == 1) whose tile has a
// course map is cut into bands one tile high, each q rows of the grid (grid.w, or grid.x, a whole number)
// as spectex_course_vertex reads them (after adding SPX_COURSE_ROUND): band b = (the row (column) index
// of g + q lead / size) / q, exact in uint, lead = round(SPX_COURSE_ROUND size / q) texels, picks entry
// ((h & 0xFFFF) SPX_LUT_SIZE) >> 16, h = lowbias32(b ^ lowbias32(key ^ SPX_BAND_SALT)), of the
// course-start table (the row after the map): f, the first line of one of the tile's courses; the band's
// courses start there, the shift (f + lead) / size.
vec2 spectex_course_band(SPX_TEX_ARG(lut), vec2 g, SPX_UINT base_i, SPX_UINT base_j, SPX_UINT key, vec2 snap,
                         vec2 tex_size, vec4 grid, float cell_row, float lut_rows) {
    bool rows = snap.y == 1.0 && snap.x >= tex_size.x;
    if (cell_row < 0.0 || !(rows || (snap.x == 1.0 && snap.y >= tex_size.y))) {
        return vec2(0.0);
    }
    float size = rows ? tex_size.y : tex_size.x;
    float qf = floor((rows ? grid.w : grid.x) + 0.5);
    float lead = floor(SPX_COURSE_ROUND * size / qf + 0.5);
    SPX_UINT gridline = (rows ? base_j : base_i) + SPX_UINT(int(floor((rows ? g.y : g.x) + qf * lead / size)));
    SPX_UINT h = spectex_hash((gridline / SPX_UINT(int(qf))) ^ spectex_hash(key ^ SPX_BAND_SALT));
    float e = float(int(((h & 65535u) * SPX_UINT(SPX_LUT_SIZE)) >> 16u));
    float row = cell_row + ceil(tex_size.x * tex_size.y / float(SPX_LUT_SIZE));
    // (a macro's arguments on one line: Godot's preprocessor takes no line break inside them)
    vec2 uv = vec2((e + 0.5) * (1.0 / float(SPX_LUT_SIZE)), (row + 0.5) / (4.0 * lut_rows));
    float shift = (SPX_LOD(lut, uv, 0.0).x + lead) / size;
    return rows ? vec2(0.0, shift) : vec2(shift, 0.0);
}

// The offset of the patch a layer with a cell map shows whole at st (stochastic.cell_vertex), and 1 (0:
// blend at the point instead); snapped along one axis only (courses), that of spectex_course_vertex;
// snapped along both, that of the vertex nearest the centre of the cell
// under st; free along both axes, that of the vertex of g's triangle whose own patch's cell under the point
// scores highest at its centre (spectex_cell_score), 0 (and an offset of no meaning) where none scores 1 or more.
vec3 spectex_cell_offset(SPX_TEX_ARG(lut), vec2 st, vec2 g, SPX_UINT base_i, SPX_UINT base_j, SPX_UINT key,
                         vec2 snap, vec2 tex_size, vec4 grid, float cell_row, float lut_rows) {
    vec2 inv_size = 1.0 / tex_size;
    vec2 win;
    vec2 shift = vec2(0.0);
    float best = 1.0;
    if ((snap.x < tex_size.x) != (snap.y < tex_size.y)) {
        vec3 course = spectex_course_vertex(SPX_TEX(lut), st, g, base_i, base_j, key, snap, tex_size, grid,
                                            cell_row, lut_rows);
        win = course.xy;
        shift = (snap.y < tex_size.y) ? vec2(course.z * inv_size.x, 0.0) : vec2(0.0, course.z * inv_size.y);
    } else if (snap.x < tex_size.x || snap.y < tex_size.y) {
        win = spectex_nearest_vertex(spectex_cell_centre(SPX_TEX(lut), st, g, tex_size, grid, cell_row, lut_rows));
    } else {
        vec2 c = floor(g);
        vec2 f = g - c;
        float d = (f.x + f.y < 1.0) ? 0.0 : 1.0;
        win = c + vec2(d, d);  // (kept only where a vertex scores: else the blend is drawn)
        best = 0.0;
        for (int k = 0; k < 3; k++) {
            // the triangle's vertices in stochastic.triangle_vertices' order: (d, d), (1 - d, d), (d, 1 - d)
            vec2 vk = c + ((k == 0) ? vec2(d, d) : ((k == 1) ? vec2(1.0 - d, d) : vec2(d, 1.0 - d)));
            vec2 off = spectex_vertex_offset(SPX_UINT(int(vk.x)) + base_i, SPX_UINT(int(vk.y)) + base_j, key,
                                             tex_size, inv_size, snap);
            float score = spectex_cell_score(spectex_cell_centre(SPX_TEX(lut), st + off, g, tex_size, grid,
                                                                 cell_row, lut_rows), vk);
            if (score > best) {
                best = score;
                win = vk;
            }
        }
    }
    return vec3(spectex_vertex_offset(SPX_UINT(int(win.x)) + base_i, SPX_UINT(int(win.y)) + base_j, key,
                                      tex_size, inv_size, snap) + shift, (best >= 1.0) ? 1.0 : 0.0);
}

// The blended Gaussian value at st of the three patches of the triangle holding grid
// point g (relative to the vertex (base_i, base_j)) (docs/sampling.md, 6b): lower
// (f.x + f.y < 1) with vertices (0, 0), (1, 0), (0, 1) of the cell, upper with (1, 1),
// (0, 1), (1, 0); as d = 0 or 1: (d, d), (1 - d, d), (d, 1 - d), so that the first two
// share their row's hash; the weights as |.| of one expression for both.
vec4 spectex_patches_at(SPX_TEX_ARG(gauss), vec2 st, vec2 g, SPX_UINT base_i, SPX_UINT base_j, SPX_UINT key,
                        vec2 snap, vec2 tex_size, float lam, float patch_lod) {
    vec2 c = floor(g);
    vec2 f = g - c;
    float fs = f.x + f.y;
    bool lower = fs < 1.0;
    SPX_UINT d = lower ? 0u : 1u;
    float e = lower ? 0.0 : 1.0;
    SPX_UINT i0 = SPX_UINT(int(c.x)) + base_i;
    SPX_UINT j0 = SPX_UINT(int(c.y)) + base_j;
    SPX_UINT hj = spectex_hash((j0 + d) ^ key);
    SPX_UINT hk = spectex_hash((j0 + 1u - d) ^ key);
    vec3 w = abs(vec3(1.0 - fs, e - f.x, e - f.y));
    // sharpened (stochastic.sharpen_weights): raised to the power 2^sh and renormalised,
    // sh = clamp(patch_lod - lambda, 0, SPX_WEIGHT_SQUARINGS) (2^sh: the patch's width in pixels,
    // at most 2^SPX_WEIGHT_SQUARINGS), the linear mix of the powers 2^floor(sh) and 2^(floor(sh) + 1)
    float sh = clamp(patch_lod - lam, 0.0, float(SPX_WEIGHT_SQUARINGS));
    float ke = floor(sh);
    vec3 ws = w;
    for (int k = 0; k < SPX_WEIGHT_SQUARINGS; k++) {
        if (float(k) < ke) {
            ws = ws * ws;
        }
    }
    vec3 wn = ws * ws;
    ws = ws * (1.0 / (ws.x + ws.y + ws.z));
    w = ws + (sh - ke) * (wn * (1.0 / (wn.x + wn.y + wn.z)) - ws);
    vec2 inv_size = 1.0 / tex_size;
    vec4 x1 = SPX_LOD(gauss, st + spectex_hash_offset(spectex_hash((i0 + d) ^ hj), tex_size, inv_size, snap), lam);
    vec4 x2 = SPX_LOD(gauss, st + spectex_hash_offset(spectex_hash((i0 + 1u - d) ^ hj), tex_size, inv_size, snap), lam);
    vec4 x3 = SPX_LOD(gauss, st + spectex_hash_offset(spectex_hash((i0 + d) ^ hk), tex_size, inv_size, snap), lam);
    // the weights sum to 1: sum w_i (x_i - m) = sum w_i x_i - m
    vec4 gb = (w.x * x1 + w.y * x2 + w.z * x3 - SPX_GAUSS_MEAN) * (1.0 / length(w)) + SPX_GAUSS_MEAN;
    // kept between the three sources per channel (stochastic.keep_between): no value none of them has
    return clamp(gb, min(x1, min(x2, x3)), max(x1, max(x2, x3)));
}

// One stochastic sample at lambda: st the tile coordinates, g the same point
// in skewed grid coordinates relative to the grid vertex (base_i, base_j),
// tex_size the level-0 width and height, snap the layer's snap counts
// (spectex_hash_offset); three patches of the Gaussianised tile `gauss`, each
// offset by its vertex's hash, blended with the barycentric weights preserving
// the variance (spectex_patches_at), then the layer's row `lut_row0` (+ level) of
// the tables and the inverse decorrelation (origin + v.x b0 + v.y b1 + v.z b2,
// b0..b2 the basis's columns). RGBA in [0, 1]. A layer with a cell map
// (cell_row >= 0; grid: the tile -> grid map) takes its structural cell's one
// patch whole (spectex_cell_offset) up to lambda = l_c, the blend at the point
// from l_c + 1 on, the linear mix of the two between; l_c = max(SPX_SHARP_LOD,
// log2 of the snap's shorter period in texels - SPX_CELL_LOD_MARGIN); free cells at every level.
vec4 spectex_sample_stochastic(SPX_TEX_ARG(gauss), SPX_TEX_ARG(lut), vec2 st, vec2 g, SPX_UINT base_i,
                               SPX_UINT base_j, SPX_UINT key, vec2 snap, vec2 tex_size, float lam, int min_filter, float q,
                               float lut_row0, float lut_rows, vec3 b0, vec3 b1, vec3 b2, vec3 origin, vec4 grid,
                               float cell_row) {
    vec2 period = tex_size / snap;
    float tm = clamp(lam - max(SPX_SHARP_LOD, log2(min(period.x, period.y)) - SPX_CELL_LOD_MARGIN), 0.0, 1.0);
    if (snap.x >= tex_size.x || snap.y >= tex_size.y) {
        tm = 0.0;  // free cells and courses hold at every level (stochastic.cell_mix)
    }
    bool cells = cell_row >= 0.0 && tm < 1.0;
    vec4 gb = vec4(0.0);
    if (cell_row >= 0.0) {  // a wall of courses of their own heights: its band's courses (else 0)
        st += spectex_course_band(SPX_TEX(lut), g, base_i, base_j, key, snap, tex_size, grid, cell_row, lut_rows);
    }
    if (cells) {
        // (a macro's arguments on one line: Godot's preprocessor takes no line break inside them)
        vec3 off = spectex_cell_offset(SPX_TEX(lut), st, g, base_i, base_j, key, snap, tex_size, grid, cell_row,
                                       lut_rows);
        if (off.z > 0.5) {
            gb = SPX_LOD(gauss, st + off.xy, lam);
        } else {
            tm = 1.0;  // the blend at the point
        }
    }
    if (!cells || tm > 0.0) {
        // log2 of the patch's side in level-0 texels (grid.x = 1 / patch: stochastic.patch_lod)
        vec4 gp = spectex_patches_at(SPX_TEX(gauss), st, g, base_i, base_j, key, snap, tex_size, lam,
                                     log2(tex_size.x / grid.x));
        gb = cells ? gb + tm * (gp - gb) : gp;
    }
    vec4 v = spectex_lut(SPX_TEX(lut), gb, lut_row0, spectex_lut_level(lam, min_filter, q), lut_rows);
    return clamp(vec4(origin + v.x * b0 + v.y * b1 + v.z * b2, v.w), 0.0, 1.0);
}

// Sections 3, 5 and 6b: lambda from the un-offset derivatives of (s, t),
// then stochastic samples at that lambda (with SPX_ANISO, N of them along
// the major axis, each with its own grid position, averaged). grid: the
// tile -> skewed grid map (m00, m01, m10, m11).
vec4 spectex_sample_stochastic_grad(SPX_TEX_ARG(gauss), SPX_TEX_ARG(lut), vec2 st, vec2 g, SPX_UINT base_i,
                                    SPX_UINT base_j, SPX_UINT key, vec2 snap, vec2 dx, vec2 dy, vec2 tex_size,
                                    float max_aniso, vec4 grid, int min_filter, float q, float lut_row0,
                                    float lut_rows, vec3 b0, vec3 b1, vec3 b2, vec3 origin, float cell_row) {
    float lam;
    vec2 d;
    float n = spectex_footprint(dx, dy, tex_size, max_aniso, lam, d);
#if SPX_ANISO
    if (n > 1.0) {
        vec2 dg = vec2(grid.x * d.x + grid.y * d.y, grid.z * d.x + grid.w * d.y);
        vec4 acc = vec4(0.0, 0.0, 0.0, 0.0);
        for (float i = 1.0; i <= n; i += 1.0) {
            float fi = i / (n + 1.0) - 0.5;
            acc += spectex_sample_stochastic(SPX_TEX(gauss), SPX_TEX(lut), st + fi * d, g + fi * dg, base_i,
                                             base_j, key, snap, tex_size, lam, min_filter, q, lut_row0, lut_rows,
                                             b0, b1, b2, origin, grid, cell_row);
        }
        return acc / n;
    }
#endif
    return spectex_sample_stochastic(SPX_TEX(gauss), SPX_TEX(lut), st, g, base_i, base_j, key, snap, tex_size,
                                     lam, min_filter, q, lut_row0, lut_rows, b0, b1, b2, origin, grid, cell_row);
}
#endif

// Section 6: the fine blend's fade (SPX_BLEND_FINE) at a layer's isotropic
// lambda lam (log2 of the longer footprint edge in level-0 texels): 1 up to
// SPX_FADE_START, 0 from SPX_FADE_END, linear between.
float spectex_fade(float lam) {
    return clamp((SPX_FADE_END - lam) * (1.0 / (SPX_FADE_END - SPX_FADE_START)), 0.0, 1.0);
}

// The isotropic lambda of the derivatives dx, dy of (s, t) (tex_size: level-0
// width, height), for spectex_fade.
float spectex_fade_lod(vec2 dx, vec2 dy, vec2 tex_size) {
    return log2(max(max(length(dx * tex_size), length(dy * tex_size)), SPX_LOD_FLOOR));
}

// Section 6, the overlay blend of one channel c with d = a (2 x - 1).
float spectex_overlay(float c, float d) {
    if (c < 0.5) {
        return c * (1.0 + d);
    }
    return 1.0 - (1.0 - c) * (1.0 - d);
}

// Section 6: the colour after a layer's sample x (RGBA) goes over c.
// blend: SPX_BLEND_FIRST (the first drawn layer: sets the colour),
// SPX_BLEND_ALPHA, SPX_BLEND_DETAIL, SPX_BLEND_VARIANCE (mean: the
// layer's tile mean colour), SPX_BLEND_FINE (the variance blend with the
// alpha times spectex_fade(lam), lam the layer's isotropic lambda; unused
// by the other blends) or SPX_BLEND_COVER (the variance blend with the alpha
// raised to 1 - (1 - a) spectex_fade(lam): the layers before it fade out
// where their periods shrink to a few pixels) or SPX_BLEND_OVERLAY (with
// d = a (2 x - 1): c (1 + d) below mid-grey, 1 - (1 - c)(1 - d) from it;
// black and white stay). Pass a constant and the branches fold away.
vec3 spectex_blend(int blend, vec3 c, vec4 x, float opacity, vec3 mean, float lam) {
    float a = x.a * opacity;
    if (blend == SPX_BLEND_FIRST) {
        return x.rgb;
    } else if (blend == SPX_BLEND_ALPHA) {
        return a * x.rgb + (1.0 - a) * c;
    } else if (blend == SPX_BLEND_DETAIL) {
        return 2.0 * x.rgb * c;
    } else if (blend == SPX_BLEND_OVERLAY) {
        vec3 d = a * (2.0 * x.rgb - 1.0);
        return vec3(spectex_overlay(c.r, d.r), spectex_overlay(c.g, d.g), spectex_overlay(c.b, d.b));
    } else if (blend == SPX_BLEND_FINE) {
        a *= spectex_fade(lam);
    } else if (blend == SPX_BLEND_COVER) {
        a = 1.0 - (1.0 - a) * spectex_fade(lam);
    }
    return mean + (a * (x.rgb - mean) + (1.0 - a) * (c - mean)) / sqrt(a * a + (1.0 - a) * (1.0 - a));
}

// Section 6, the layer step: a periodic layer over c at ground point p (metres
// from the anchor point) with footprint jx, jy (its derivatives along the
// picture's x and y): the layer's coordinates (anchor: its tile coordinates
// of the anchor point; m: its map), the sample at the footprint's level of
// detail (a fine layer isotropic: it fades out before anisotropy would matter),
// the blend (fade_bias: added to the fade's lambda, log2 of the supersampling
// factor when supersampled). The renderer's main() and the engines' shaders
// call this same step.
vec3 spectex_layer(int blend, SPX_TEX_ARG(tile), vec3 c, vec2 anchor, vec4 m, float opacity, vec3 mean, vec2 p,
                   vec2 jx, vec2 jy, vec2 tex_size, float max_aniso, float fade_bias) {
    vec2 st = spectex_layer_coords(anchor, m, p);
    vec2 dx = spectex_layer_deriv(m, jx);
    vec2 dy = spectex_layer_deriv(m, jy);
    vec4 x = spectex_sample_grad(SPX_TEX(tile), st, dx, dy, tex_size, (blend == SPX_BLEND_FINE) ? 1.0 : max_aniso);
    float lam = (blend == SPX_BLEND_FINE || blend == SPX_BLEND_COVER) ? spectex_fade_lod(dx, dy, tex_size) : 0.0;
    return spectex_blend(blend, c, x, opacity, mean, lam + fade_bias);
}

#ifdef SPX_UINT
// Sections 6 and 6b, the layer step of a stochastic layer: as spectex_layer,
// with the layer's grid position relative to the anchor's (ganchor: the
// anchor's grid position minus its vertex (base_i, base_j); gm: the tile ->
// grid map), its hash key, its snap counts (spectex_hash_offset), its first
// table row and its decorrelation (b0, b1, b2 the basis's columns, origin), the
// minification filter's code, the last mip level lut_q and the table's rows per
// channel lut_rows.
vec3 spectex_layer_stochastic(int blend, SPX_TEX_ARG(gauss), SPX_TEX_ARG(lut), vec3 c, vec2 anchor, vec2 ganchor,
                              SPX_UINT base_i, SPX_UINT base_j, vec4 m, vec4 gm, SPX_UINT key, vec2 snap,
                              float cell_row, float lut_row, vec3 b0, vec3 b1, vec3 b2, vec3 origin, float opacity, vec3 mean,
                              vec2 p, vec2 jx, vec2 jy, vec2 tex_size, float max_aniso, int min_filter, float lut_q,
                              float lut_rows, float fade_bias) {
    vec2 rel = spectex_layer_deriv(m, p);  // tile coordinates relative to the anchor
    vec2 g = ganchor + vec2(gm.x * rel.x + gm.y * rel.y, gm.z * rel.x + gm.w * rel.y);
    vec4 x = spectex_sample_stochastic_grad(SPX_TEX(gauss), SPX_TEX(lut), anchor + rel, g, base_i, base_j, key,
                                            snap, spectex_layer_deriv(m, jx), spectex_layer_deriv(m, jy), tex_size,
                                            (blend == SPX_BLEND_FINE) ? 1.0 : max_aniso, gm, min_filter, lut_q,
                                            lut_row, lut_rows, b0, b1, b2, origin, cell_row);
    float lam = (blend == SPX_BLEND_FINE || blend == SPX_BLEND_COVER)
        ? spectex_fade_lod(spectex_layer_deriv(m, jx), spectex_layer_deriv(m, jy), tex_size) : 0.0;
    return spectex_blend(blend, c, x, opacity, mean, lam + fade_bias);
}
#endif

// Section 7: distance haze over the ground colour c at distance dist.
vec3 spectex_haze(vec3 c, float dist, vec3 horizon, float haze_distance) {
    return horizon + exp(-dist / haze_distance) * (c - horizon);
}

// Section 7: the sky at elevation d_z / |d| (> 0).
vec3 spectex_sky(float elevation, vec3 horizon, vec3 zenith) {
    return horizon + (1.0 - exp(-SPX_SKY_FALLOFF * elevation)) * (zenith - horizon);
}
