// The brute-force oracle of the rasterization tests (test_raster.cpp, test_raster3d.cpp), written// independently of ConservativeRaster.hpp.
//
//
// The reference ("oracle") below is written independently of ConservativeRaster.hpp: per voxel it computes,
// in long double,
//   touchDist    the Euclidean distance between the closed voxel box and the closed shape (0 when they meet;
//                polygons: separating-axis test, then vertex/edge distances),
//   innerMargin  how far the closed voxel lies inside the closed shape (>= 0 iff it is inside; convex
//                shapes: exact corner tests),
// and sd(p), a signed distance-like function (<= 0 iff p is in the closed shape) used for dense sampling.
// The contract checked for every voxel of the grid:
//   - each voxel is emitted at most once, only in-grid voxels are emitted, in increasing linear order;
//   - inner => touched;
//   - inner => innerMargin >= -kTolInner, and every one of 9x9 (3D: 5x5x5) sample points incl. corners is
//     in the shape grown by kTolInner (O under-estimates, up to the documented 1e-9 voxel face snapping);
//   - touchDist <= kTolSound => touched (I over-estimates; zero false negatives);
//   - innerMargin >= kTight => inner (O is tight), touchDist >= kTight => not touched (I is tight).
// kTolSound only absorbs the oracle's own rounding; it is far below the rasterizer's kConservativeSlack.
#pragma once

#include "rgvc/grid/ConservativeRaster.hpp"
#include "rgvc/grid/GridGeometry.hpp"
#include "rgvc/grid/Shapes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>


using namespace rgvc;

namespace Catch {
template <> struct StringMaker<std::pair<int, int>> {
    static std::string convert(const std::pair<int, int>& p) {
        // Appended, not "(" + std::string&&: GCC 12 warns a false -Wrestrict on that operator+ when
        // inlined (GCC bug 105329).
        std::string s = "(";
        s += std::to_string(p.first);
        s += ',';
        s += std::to_string(p.second);
        s += ')';
        return s;
    }
};
} // namespace Catch

namespace raster_oracle {

using L = long double;

constexpr L kTolSound = 1e-11L; // oracle rounding allowance (voxel units)
// ConservativeRaster.hpp: "O may only under-estimate the opaque region (up to a 1e-9 voxel snapping of faces
// to voxel boundaries)": an inner voxel may poke out of its shape by at most kConservativeSlack.
constexpr L kTolInner = L(kConservativeSlack) + kTolSound;
constexpr L kTight = 1e-6L;     // tightness margin (voxel units)

// ---------------------------------------------------------------------------------------------------
// Describing shapes in failure messages.

inline std::string describe(const Shape<2>& s) {
    std::ostringstream o;
    o << std::setprecision(17);
    if (auto* b = std::get_if<Ball<2>>(&s)) {
        o << "Ball2{center=(" << b->center.x << ", " << b->center.y << "), radius=" << b->radius << "}";
    } else if (auto* x = std::get_if<Box<2>>(&s)) {
        o << "Box2{min=(" << x->min.x << ", " << x->min.y << "), max=(" << x->max.x << ", " << x->max.y << ")}";
    } else {
        const auto& p = std::get<ConvexPolygon>(s);
        o << "ConvexPolygon{";
        for (std::size_t i = 0; i < p.points.size(); ++i)
            o << (i ? ", " : "") << "(" << p.points[i].x << ", " << p.points[i].y << ")";
        o << "}";
    }
    return o.str();
}

inline std::string describe(const Shape<3>& s) {
    std::ostringstream o;
    o << std::setprecision(17);
    if (auto* b = std::get_if<Ball<3>>(&s)) {
        o << "Ball3{center=(" << b->center.x << ", " << b->center.y << ", " << b->center.z
          << "), radius=" << b->radius << "}";
    } else if (auto* x = std::get_if<Box<3>>(&s)) {
        o << "Box3{min=(" << x->min.x << ", " << x->min.y << ", " << x->min.z << "), max=(" << x->max.x << ", "
          << x->max.y << ", " << x->max.z << ")}";
    } else if (const auto* m = std::get_if<MeshSolid>(&s)) {
        o << "MeshSolid{" << (m->model() ? m->model()->mesh.triangles.size() : 0) << " triangles, "
          << (m->closed() ? "closed" : "open") << ", scale " << m->scale() << ", offset (" << m->offset().x << ", "
          << m->offset().y << ", " << m->offset().z << ")}";
    } else {
        const auto& p = std::get<ConvexPolytope>(s);
        o << "ConvexPolytope{points=[";
        for (std::size_t i = 0; i < p.vertices.size(); ++i)
            o << (i ? ", " : "") << "[" << p.vertices[i].x << ", " << p.vertices[i].y << ", " << p.vertices[i].z << "]";
        o << "], planes=" << p.planes.size() << ", tolerance=" << p.tolerance << "}";
    }
    return o.str();
}

// ---------------------------------------------------------------------------------------------------
// The 2D oracle.

inline L pointSegmentDistance(L px, L py, L ax, L ay, L bx, L by) {
    L ex = bx - ax, ey = by - ay;
    L len2 = ex * ex + ey * ey;
    L t = len2 > 0 ? ((px - ax) * ex + (py - ay) * ey) / len2 : 0;
    t = std::clamp(t, L(0), L(1));
    L dx = px - (ax + t * ex), dy = py - (ay + t * ey);
    return std::sqrt(dx * dx + dy * dy);
}

inline L pointBoxDistance(L px, L py, L x0, L y0, L x1, L y1) {
    L dx = std::max({x0 - px, L(0), px - x1});
    L dy = std::max({y0 - py, L(0), py - y1});
    return std::sqrt(dx * dx + dy * dy);
}

struct Ref2 {
    enum Kind { Circle, Rect, Poly } kind = Circle;
    L cx = 0, cy = 0, r = 0;                // circle
    L bx0 = 0, by0 = 0, bx1 = 0, by1 = 0;   // box
    std::vector<L> px, py, nx, ny, nc;      // polygon (ccw), outward unit normals: n.p <= c inside
    std::vector<double> fnx, fny, fnc;      // the same normals in double, for fast dense sampling
    L minx = 0, miny = 0, maxx = 0, maxy = 0; // bounds

    static Ref2 circle(L cx, L cy, L r) {
        Ref2 f;
        f.kind = Circle;
        f.cx = cx, f.cy = cy, f.r = r;
        f.minx = cx - r, f.maxx = cx + r, f.miny = cy - r, f.maxy = cy + r;
        return f;
    }
    static Ref2 box(L x0, L y0, L x1, L y1) {
        Ref2 f;
        f.kind = Rect;
        f.bx0 = x0, f.by0 = y0, f.bx1 = x1, f.by1 = y1;
        f.minx = x0, f.miny = y0, f.maxx = x1, f.maxy = y1;
        return f;
    }
    /// Points counter-clockwise.
    static Ref2 poly(std::vector<L> xs, std::vector<L> ys) {
        Ref2 f;
        f.kind = Poly;
        f.px = std::move(xs);
        f.py = std::move(ys);
        const std::size_t n = f.px.size();
        f.minx = *std::min_element(f.px.begin(), f.px.end());
        f.maxx = *std::max_element(f.px.begin(), f.px.end());
        f.miny = *std::min_element(f.py.begin(), f.py.end());
        f.maxy = *std::max_element(f.py.begin(), f.py.end());
        for (std::size_t i = 0; i < n; ++i) {
            L ex = f.px[(i + 1) % n] - f.px[i], ey = f.py[(i + 1) % n] - f.py[i];
            L len = std::sqrt(ex * ex + ey * ey);
            L ux = ey / len, uy = -ex / len; // outward for a counter-clockwise polygon
            f.nx.push_back(ux);
            f.ny.push_back(uy);
            f.nc.push_back(ux * f.px[i] + uy * f.py[i]);
            f.fnx.push_back((double)ux);
            f.fny.push_back((double)uy);
            f.fnc.push_back((double)f.nc.back());
        }
        return f;
    }

    /// <= 0 iff p is in the closed shape (Euclidean signed distance for circles and, outside, a lower bound
    /// of it for boxes/polygons; inside, the exact depth for convex shapes).
    L sd(L x, L y) const {
        switch (kind) {
        case Circle: return std::sqrt((x - cx) * (x - cx) + (y - cy) * (y - cy)) - r;
        case Rect: return std::max({bx0 - x, x - bx1, by0 - y, y - by1});
        default: {
            L m = -std::numeric_limits<L>::infinity();
            for (std::size_t i = 0; i < nx.size(); ++i) m = std::max(m, nx[i] * x + ny[i] * y - nc[i]);
            return m;
        }
        }
    }

    /// sd in double precision (rounding ~1e-14 voxel, far below the tolerances it is compared with).
    double sdFast(double x, double y) const {
        switch (kind) {
        case Circle: return std::sqrt((x - (double)cx) * (x - (double)cx) + (y - (double)cy) * (y - (double)cy)) - (double)r;
        case Rect: return std::max({(double)bx0 - x, x - (double)bx1, (double)by0 - y, y - (double)by1});
        default: {
            double m = -std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i < fnx.size(); ++i) m = std::max(m, fnx[i] * x + fny[i] * y - fnc[i]);
            return m;
        }
        }
    }

    /// Distance between the closed box [x0,x1]x[y0,y1] and the closed shape; 0 when they meet. (Polygons:
    /// exact below kTight, a lower bound >= kTight above.)
    L touchDist(L x0, L y0, L x1, L y1) const {
        switch (kind) {
        case Circle: return std::max(L(0), pointBoxDistance(cx, cy, x0, y0, x1, y1) - r);
        case Rect: {
            L gx = std::max({L(0), bx0 - x1, x0 - bx1});
            L gy = std::max({L(0), by0 - y1, y0 - by1});
            return std::sqrt(gx * gx + gy * gy);
        }
        default: {
            // Separating axis theorem: the box's axes and the polygon's edge normals. The largest gap along
            // these axes is > 0 iff they are disjoint, and a lower bound of their distance.
            L gap = std::max({minx - x1, x0 - maxx, miny - y1, y0 - maxy});
            const L cxs[4] = {x0, x1, x0, x1}, cys[4] = {y0, y0, y1, y1};
            for (std::size_t i = 0; i < nx.size(); ++i) {
                L m = std::numeric_limits<L>::infinity();
                for (int k = 0; k < 4; ++k) m = std::min(m, nx[i] * cxs[k] + ny[i] * cys[k] - nc[i]);
                gap = std::max(gap, m);
            }
            if (gap <= 0) return 0;
            if (gap >= kTight) return gap; // only compared with kTolSound and kTight: a lower bound will do
            // Disjoint convex polygons: the closest pair has a vertex of one of them.
            L d = std::numeric_limits<L>::infinity();
            const std::size_t n = px.size();
            for (std::size_t i = 0; i < n; ++i) d = std::min(d, pointBoxDistance(px[i], py[i], x0, y0, x1, y1));
            for (int k = 0; k < 4; ++k)
                for (std::size_t i = 0; i < n; ++i)
                    d = std::min(d, pointSegmentDistance(cxs[k], cys[k], px[i], py[i], px[(i + 1) % n], py[(i + 1) % n]));
            return d;
        }
        }
    }

    /// >= 0 iff the closed box lies in the closed shape; then its distance from the shape's boundary.
    L innerMargin(L x0, L y0, L x1, L y1) const {
        switch (kind) {
        case Circle: {
            L fx = std::max(std::fabs(cx - x0), std::fabs(cx - x1));
            L fy = std::max(std::fabs(cy - y0), std::fabs(cy - y1));
            return r - std::sqrt(fx * fx + fy * fy);
        }
        case Rect: return std::min({x0 - bx0, bx1 - x1, y0 - by0, by1 - y1});
        default: {
            // Convex: the box is inside iff its four corners are.
            L m = std::numeric_limits<L>::infinity();
            const L cxs[4] = {x0, x1, x0, x1}, cys[4] = {y0, y0, y1, y1};
            for (std::size_t i = 0; i < nx.size(); ++i)
                for (int k = 0; k < 4; ++k) m = std::min(m, nc[i] - (nx[i] * cxs[k] + ny[i] * cys[k]));
            return m;
        }
        }
    }

    bool outsideGrid(IVec2 res) const { return minx < 0 || miny < 0 || maxx > res.x || maxy > res.y; }
};

inline Ref2 refOf(const Shape<2>& s) {
    if (auto* b = std::get_if<Ball<2>>(&s)) return Ref2::circle(b->center.x, b->center.y, b->radius);
    if (auto* x = std::get_if<Box<2>>(&s)) return Ref2::box(x->min.x, x->min.y, x->max.x, x->max.y);
    const auto& p = std::get<ConvexPolygon>(s);
    std::vector<L> xs, ys;
    for (const Vec2& q : p.points) {
        xs.push_back(q.x);
        ys.push_back(q.y);
    }
    return Ref2::poly(xs, ys);
}

struct Stats {
    long shapes = 0, voxels = 0, inner = 0, touched = 0, outside = 0;
    long contact = 0;      // touched only at the boundary: a voxel shrunk by 1e-7 no longer touches
    long innerContact = 0; // inside with margin in [0, 1e-6): the rasterizer may or may not mark them
    long sampleChecks = 0;
};

template <int D> std::size_t linearOf(const IVec<D>& v, const IVec<D>& res) {
    std::size_t i = std::size_t(v[D - 1]);
    for (int a = D - 2; a >= 0; --a) i = i * std::size_t(res[a]) + std::size_t(v[a]);
    return i;
}

/// Collects what the rasterizer emits, checking in-grid, at most once and increasing order.
template <int D> struct Emitted {
    std::vector<std::uint8_t> hit;
    std::string error;
    long count = 0;
    std::int64_t last = -1;
    IVec<D> res;
    explicit Emitted(IVec<D> r) : res(r) {
        std::size_t n = 1;
        for (int a = 0; a < D; ++a) n *= std::size_t(r[a]);
        hit.assign(n, 0);
    }
    void operator()(const IVec<D>& v) {
        ++count;
        for (int a = 0; a < D; ++a)
            if (v[a] < 0 || v[a] >= res[a]) {
                if (error.empty()) {
                    std::ostringstream o;
                    o << "emitted out-of-grid voxel (" << v[0] << ", " << v[1];
                    if constexpr (D == 3) o << ", " << v[2];
                    o << ")";
                    error = o.str();
                }
                return;
            }
        std::size_t i = linearOf<D>(v, res);
        if (hit[i] && error.empty()) error = "voxel emitted twice";
        if (std::int64_t(i) <= last && error.empty()) error = "voxels not emitted in increasing linear order";
        last = std::int64_t(i);
        hit[i] = 1;
    }
};

/// Runs the rasterizer on `s` (grid of resolution res) into inner and touched, and counts the shape into
/// st. Returns "" or the first failure: an emission error (Emitted), or extendsOutsideGrid disagreeing with
/// the oracle's ref.outsideGrid(res) where checkOutside.
template <int D, class Ref>
std::string rasterizeAndCount(const Shape<D>& s, const Ref& ref, IVec<D> res, bool checkOutside, Stats& st, Emitted<D>& inner,
                              Emitted<D>& touched) {
    forEachInnerVoxel<D>(s, res, [&](const IVec<D>& v) { inner(v); });
    forEachTouchedVoxel<D>(s, res, [&](const IVec<D>& v) { touched(v); });
    if (!inner.error.empty()) return "inner: " + inner.error;
    if (!touched.error.empty()) return "touched: " + touched.error;
    ++st.shapes;
    st.inner += inner.count;
    st.touched += touched.count;
    const bool out = extendsOutsideGrid<D>(s, res);
    if (out) ++st.outside;
    if (checkOutside && out != ref.outsideGrid(res)) return std::string("extendsOutsideGrid returned ") + (out ? "true" : "false");
    return "";
}

/// A voxel's failure: "<what> at voxel (x, y[, z]), touchDist=<td> innerMargin=<im>", 17 digits.
template <int D> std::string voxelFailure(const char* what, const IVec<D>& v, L td, L im) {
    std::ostringstream o;
    o << std::setprecision(17) << what << " at voxel (" << v[0];
    for (int a = 1; a < D; ++a) o << ", " << v[a];
    o << "), touchDist=" << (double)td << " innerMargin=" << (double)im;
    return o.str();
}

/// Checks one 2D shape (voxel units) on a grid of resolution res. Returns "" or the first failure.
inline std::string checkShape2(const Shape<2>& s, const Ref2& ref, IVec2 res, bool selfCheckOracle, Stats& st,
                        bool checkOutside = true) {
    Emitted<2> inner(res), touched(res);
    if (std::string e = rasterizeAndCount<2>(s, ref, res, checkOutside, st, inner, touched); !e.empty()) return e;
    auto fail = [](const char* what, int x, int y, L a, L b) { return voxelFailure<2>(what, IVec2(x, y), a, b); };
    for (int y = 0; y < res.y; ++y)
        for (int x = 0; x < res.x; ++x) {
            ++st.voxels;
            const std::size_t i = std::size_t(x) + std::size_t(y) * res.x;
            const bool isInner = inner.hit[i], isTouched = touched.hit[i];
            const L td = ref.touchDist(x, y, x + 1, y + 1);
            const L im = ref.innerMargin(x, y, x + 1, y + 1);
            if (isInner && !isTouched) return fail("inner but not touched", x, y, td, im);
            if (td <= kTolSound && !isTouched) return fail("touches the shape but not reported touched", x, y, td, im);
            if (td >= kTight && isTouched) return fail("misses the shape by >= 1e-6 but reported touched", x, y, td, im);
            if (im >= kTight && !isInner) return fail("inside the shape with margin >= 1e-6 but not inner", x, y, td, im);
            if (isInner && im < -kTolInner) return fail("reported inner but a corner is outside the shape", x, y, td, im);
            if (isTouched && td <= kTolSound && ref.touchDist(x + 1e-7L, y + 1e-7L, x + 1 - 1e-7L, y + 1 - 1e-7L) > 0)
                ++st.contact;
            if (im >= 0 && im < kTight) ++st.innerContact;
            if (isInner || selfCheckOracle) {
                // Dense sampling: 9x9 points including the corners.
                double worst = -std::numeric_limits<double>::infinity(), best = std::numeric_limits<double>::infinity();
                for (int a = 0; a <= 8; ++a)
                    for (int b = 0; b <= 8; ++b) {
                        double v = ref.sdFast(x + a / 8.0, y + b / 8.0);
                        worst = std::max(worst, v);
                        best = std::min(best, v);
                    }
                st.sampleChecks += 81;
                if (isInner && worst > kTolInner)
                    return fail("reported inner but a sample point is outside the shape", x, y, td, im);
                if (selfCheckOracle) {
                    // The oracle agrees with sampling: a sample inside the shape means the voxel touches it;
                    // an inside voxel has all samples inside.
                    if (best <= 0 && td > kTolSound) return fail("ORACLE: sample inside but touchDist > 0", x, y, td, im);
                    if (im >= 0 && worst > kTolSound) return fail("ORACLE: innerMargin >= 0 but sample outside", x, y, td, im);
                }
            }
        }
    return "";
}

// ---------------------------------------------------------------------------------------------------
// Random shapes in voxel units.

struct Gen {
    std::mt19937_64 rng;
    explicit Gen(std::uint64_t seed) : rng(seed) {}
    double uni(double a = 0, double b = 1) { return std::uniform_real_distribution<double>(a, b)(rng); }
    int irange(int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); }
    bool chance(double p) { return uni() < p; }
    double logUni(double lo, double hi) { return std::pow(10.0, uni(std::log10(lo), std::log10(hi))); }
    /// A displacement far below kConservativeSlack (or zero): breaks exact contacts by less than the slack.
    double jitter() {
        const double js[] = {0, 1e-13, 1e-12, 5e-12, 9e-12};
        return (chance(0.5) ? 1 : -1) * js[irange(0, 4)];
    }

    IVec2 resolution() {
        auto one = [&] { return chance(0.15) ? irange(1, 4) : irange(1, 64); };
        return IVec2(one(), one());
    }
    /// A coordinate in and around [0, n], often on a voxel corner, edge or centre.
    double coord(int n) {
        double c = uni(-0.3 * n - 3, 1.3 * n + 3);
        double p = uni();
        if (p < 0.3) return std::round(c);
        if (p < 0.4) return std::floor(c) + 0.5;
        return c;
    }
};

/// Monotone-chain convex hull, strictly convex, counter-clockwise.
inline std::vector<Vec2> convexHull(std::vector<Vec2> pts) {
    std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    if (pts.size() < 3) return {};
    std::vector<Vec2> h(2 * pts.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        while (k >= 2 && cross2(h[k - 1] - h[k - 2], pts[i] - h[k - 2]) <= 0) --k;
        h[k++] = pts[i];
    }
    for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross2(h[k - 1] - h[k - 2], pts[i] - h[k - 2]) <= 0) --k;
        h[k++] = pts[i];
    }
    h.resize(k - 1);
    return h;
}

inline Shape<2> randomCircle(Gen& g, IVec2 res) {
    const int n = std::max(res.x, res.y);
    Ball<2> b;
    b.center = Vec2(g.coord(res.x), g.coord(res.y));
    double q = g.uni();
    if (q < 0.15) {
        // Radii that put voxel corners exactly on the circle when the centre is on a corner (3-4-5, 5-12-13...).
        const double rs[] = {0.5, 1, 1.5, 2, 5, 10, 13, 15, 17, 25};
        b.radius = rs[g.irange(0, 9)];
    } else if (q < 0.3) {
        b.radius = g.logUni(1e-4, 0.3); // much smaller than a voxel
    } else if (q < 0.4) {
        b.radius = std::sqrt(double(g.irange(1, 300))); // through (rounded) corners
    } else if (q < 0.45) {
        b.radius = 2.0 * n + g.uni(0, 50); // larger than the grid
    } else {
        b.radius = g.uni(0.05, 0.8 * n + 1);
    }
    return b;
}

inline Shape<2> randomBox(Gen& g, IVec2 res) {
    Box<2> b;
    bool integral = g.chance(0.4);
    for (int a = 0; a < 2; ++a) {
        const int n = res[a];
        double lo = g.coord(n);
        double w;
        double q = g.uni();
        if (q < 0.2) w = g.logUni(1e-7, 1e-2);
        else if (q < 0.3) w = 2.0 * n + g.uni(0, 20);
        else w = g.uni(0.01, 0.7 * n + 1);
        if (integral) {
            lo = std::round(lo);
            if (w >= 1) w = std::round(w);
        }
        b.min[a] = lo;
        b.max[a] = lo + w;
    }
    return b;
}

inline Shape<2> randomPolygon(Gen& g, IVec2 res) {
    const int n = std::max(res.x, res.y);
    for (;;) {
        std::vector<Vec2> pts;
        const int type = g.irange(0, 8);
        const Vec2 c(g.coord(res.x), g.coord(res.y));
        if (type == 0 || type == 1) {
            // Points on a rotated ellipse.
            int m = g.irange(3, 12);
            double ra = type == 0 ? g.uni(0.05, 0.7 * n + 1) : g.logUni(1e-4, 0.5);
            double rb = ra * g.uni(0.05, 1.0);
            double rot = g.uni(0, 6.283185307179586);
            for (int k = 0; k < m; ++k) {
                double t = g.uni(0, 6.283185307179586);
                Vec2 e(ra * std::cos(t), rb * std::sin(t));
                pts.push_back(c + Vec2(e.x * std::cos(rot) - e.y * std::sin(rot), e.x * std::sin(rot) + e.y * std::cos(rot)));
            }
        } else if (type == 2) {
            // Hull of random points in a box.
            int m = g.irange(3, 20);
            double w = g.uni(0.1, n + 2), h = g.uni(0.1, n + 2);
            for (int k = 0; k < m; ++k) pts.push_back(c + Vec2(g.uni(-w, w), g.uni(-h, h)));
        } else if (type == 3) {
            // Integer vertices: edges pass exactly through voxel corners.
            int m = g.irange(3, 10);
            int w = g.irange(1, n / 2 + 2);
            IVec2 ic(int(std::round(c.x)), int(std::round(c.y)));
            for (int k = 0; k < m; ++k) pts.push_back(Vec2(ic + IVec2(g.irange(-w, w), g.irange(-w, w))));
        } else if (type == 4) {
            // Diamond with integer or half-integer centre: 45-degree edges through voxel corners.
            double k = g.irange(1, n / 2 + 2);
            Vec2 cc = g.chance(0.5) ? glm::round(c) : glm::floor(c) + 0.5;
            pts = {cc + Vec2(k, 0), cc + Vec2(0, k), cc - Vec2(k, 0), cc - Vec2(0, k)};
        } else if (type == 5) {
            // Thin sliver: a long segment widened by 1e-7 .. 1e-2.
            Vec2 a = c, b(g.coord(res.x), g.coord(res.y));
            if (b == a) continue;
            Vec2 dir = b - a;
            Vec2 nrm = Vec2(-dir.y, dir.x) / std::sqrt(lengthSquared<2>(dir));
            double t = g.logUni(1e-7, 1e-2);
            if (g.chance(0.5)) pts = {a, b, 0.5 * (a + b) + t * nrm};
            else pts = {a, b, b + t * nrm, a + t * nrm};
        } else if (type == 6) {
            // Axis-aligned rectangle with integer coordinates, as a polygon.
            IVec2 lo(int(std::round(c.x)), int(std::round(c.y)));
            IVec2 sz(g.irange(1, n / 2 + 2), g.irange(1, n / 2 + 2));
            pts = {Vec2(lo), Vec2(lo.x + sz.x, lo.y), Vec2(lo + sz), Vec2(lo.x, lo.y + sz.y)};
        } else if (type == 7) {
            // Integer-vertex rotated rectangle (edges of slope 1/2, -2 ...).
            IVec2 ic(int(std::round(c.x)), int(std::round(c.y)));
            IVec2 u(g.irange(1, 6), g.irange(-6, 6)), v(-u.y, u.x);
            int s = g.irange(1, 3), t = g.irange(1, 3);
            pts = {Vec2(ic), Vec2(ic + s * u), Vec2(ic + s * u + t * v), Vec2(ic + t * v)};
        } else {
            // A triangle much larger than the grid, or one wholly outside it.
            double big = g.chance(0.5) ? 10.0 * n + 100 : g.uni(1, 5);
            Vec2 cc = g.chance(0.5) ? c : Vec2(-big - 2, g.coord(res.y));
            for (int k = 0; k < 3; ++k) {
                double t = 2.0943951023931953 * k + g.uni(-0.5, 0.5);
                pts.push_back(cc + big * Vec2(std::cos(t), std::sin(t)));
            }
        }
        std::vector<Vec2> hull = convexHull(pts);
        if (hull.size() < 3) continue;
        Shape<2> s = ConvexPolygon{hull};
        // Half of the time, give the points clockwise: validateShape must normalise them.
        if (g.chance(0.5)) std::reverse(std::get<ConvexPolygon>(s).points.begin(), std::get<ConvexPolygon>(s).points.end());
        try {
            validateShape<2>(s, "test");
        } catch (const InvalidInput&) {
            continue;
        }
        return s;
    }
}

inline void printStats(const char* name, const Stats& st, double seconds) {
    std::printf("[raster] %-10s shapes=%ld voxels=%ld inner=%ld touched=%ld outsideGrid=%ld contact=%ld "
                "innerContact=%ld samples=%ld (%.2fs)\n",
                name, st.shapes, st.voxels, st.inner, st.touched, st.outside, st.contact, st.innerContact,
                st.sampleChecks, seconds);
}

inline double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <class MakeShape>
inline void runRandom2(const char* name, std::uint64_t seed, int count, MakeShape&& make, long minInner, long minContact) {
    auto t0 = std::chrono::steady_clock::now();
    Stats st;
    int failures = 0;
    for (int i = 0; i < count; ++i) {
        // One generator per shape: a failure reproduces from (seed, i) alone.
        Gen g(seed * 1000003ULL + std::uint64_t(i));
        IVec2 res = g.resolution();
        Shape<2> s = make(g, res);
        // Shapes on the integer lattice moved by less than the slack: near-contacts that must still count.
        if (g.chance(0.3)) s = translated<2>(s, Vec2(g.jitter(), g.jitter()));
        validateShape<2>(s, "test");
        std::string err = checkShape2(s, refOf(s), res, i < 300, st);
        if (!err.empty() && failures++ < 5) {
            FAIL_CHECK(name << " seed=" << seed << " shape #" << i << " grid " << res.x << "x" << res.y << "\n  "
                            << describe(s) << "\n  " << err);
        }
    }
    CHECK(failures == 0);
    printStats(name, st, secondsSince(t0));
    // The random families must exercise what they claim to.
    CHECK(st.shapes == count);
    CHECK(st.inner >= minInner);
    CHECK(st.contact >= minContact);
    CHECK(st.outside > 0);
    CHECK(st.outside < st.shapes);
}

// ---------------------------------------------------------------------------------------------------
// 3D oracle: balls and boxes.

struct Ref3 {
    bool ball = true;
    L c[3] = {0, 0, 0}, r = 0;
    L lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};

    L sd(const L p[3]) const {
        if (ball) {
            L s = 0;
            for (int a = 0; a < 3; ++a) s += (p[a] - c[a]) * (p[a] - c[a]);
            return std::sqrt(s) - r;
        }
        L m = -std::numeric_limits<L>::infinity();
        for (int a = 0; a < 3; ++a) m = std::max({m, lo[a] - p[a], p[a] - hi[a]});
        return m;
    }
    L touchDist(const IVec3& v) const {
        L s = 0;
        for (int a = 0; a < 3; ++a) {
            L g = ball ? std::max({c[a] - (v[a] + 1), L(0), v[a] - c[a]})
                       : std::max({L(0), lo[a] - (v[a] + 1), v[a] - hi[a]});
            s += g * g;
        }
        return ball ? std::max(L(0), std::sqrt(s) - r) : std::sqrt(s);
    }
    L innerMargin(const IVec3& v) const {
        if (ball) {
            L s = 0;
            for (int a = 0; a < 3; ++a) {
                L f = std::max(std::fabs(c[a] - v[a]), std::fabs(c[a] - (v[a] + 1)));
                s += f * f;
            }
            return r - std::sqrt(s);
        }
        L m = std::numeric_limits<L>::infinity();
        for (int a = 0; a < 3; ++a) m = std::min({m, v[a] - lo[a], hi[a] - (v[a] + 1)});
        return m;
    }
    bool outsideGrid(IVec3 res) const {
        for (int a = 0; a < 3; ++a) {
            L mn = ball ? c[a] - r : lo[a], mx = ball ? c[a] + r : hi[a];
            if (mn < 0 || mx > res[a]) return true;
        }
        return false;
    }
};

inline Ref3 refOf(const Shape<3>& s) {
    Ref3 f;
    if (auto* b = std::get_if<Ball<3>>(&s)) {
        f.ball = true;
        for (int a = 0; a < 3; ++a) f.c[a] = b->center[a];
        f.r = b->radius;
    } else {
        const auto& x = std::get<Box<3>>(s);
        f.ball = false;
        for (int a = 0; a < 3; ++a) f.lo[a] = x.min[a], f.hi[a] = x.max[a];
    }
    return f;
}

inline std::string checkShape3(const Shape<3>& s, IVec3 res, Stats& st) {
    const Ref3 ref = refOf(s);
    Emitted<3> inner(res), touched(res);
    if (std::string e = rasterizeAndCount<3>(s, ref, res, true, st, inner, touched); !e.empty()) return e;
    auto* const fail = &voxelFailure<3>;
    for (int z = 0; z < res.z; ++z)
        for (int y = 0; y < res.y; ++y)
            for (int x = 0; x < res.x; ++x) {
                ++st.voxels;
                const IVec3 v(x, y, z);
                const std::size_t i = linearOf<3>(v, res);
                const bool isInner = inner.hit[i], isTouched = touched.hit[i];
                const L td = ref.touchDist(v), im = ref.innerMargin(v);
                if (isInner && !isTouched) return fail("inner but not touched", v, td, im);
                if (td <= kTolSound && !isTouched) return fail("touches the shape but not reported touched", v, td, im);
                if (td >= kTight && isTouched) return fail("misses the shape by >= 1e-6 but reported touched", v, td, im);
                if (im >= kTight && !isInner) return fail("inside the shape with margin >= 1e-6 but not inner", v, td, im);
                if (isInner && im < -kTolInner) return fail("reported inner but a corner is outside the shape", v, td, im);
                if (im >= 0 && im < kTight) ++st.innerContact;
                if (isTouched && td <= kTolSound) {
                    // Contact only: the voxel shrunk by 1e-7 misses the shape.
                    L s2 = 0;
                    for (int a = 0; a < 3; ++a) {
                        L lo = v[a] + 1e-7L, hi = v[a] + 1 - 1e-7L;
                        L gp = ref.ball ? std::max({ref.c[a] - hi, L(0), lo - ref.c[a]})
                                        : std::max({L(0), ref.lo[a] - hi, lo - ref.hi[a]});
                        s2 += gp * gp;
                    }
                    if ((ref.ball ? std::sqrt(s2) - ref.r : std::sqrt(s2)) > 0) ++st.contact;
                }
                if (isInner) {
                    for (int a = 0; a <= 4; ++a)
                        for (int b = 0; b <= 4; ++b)
                            for (int c = 0; c <= 4; ++c) {
                                const L p[3] = {x + a / L(4), y + b / L(4), z + c / L(4)};
                                if (ref.sd(p) > kTolInner)
                                    return fail("reported inner but a sample point is outside the shape", v, td, im);
                            }
                    st.sampleChecks += 125;
                }
            }
    return "";
}

// ---------------------------------------------------------------------------------------------------
// 3D oracle: convex polytopes (hulls, oriented boxes), from their points alone and independently of the
// library's hull: the facets are found by brute force over every triple of points (a plane through three
// of them with every point on one side is a supporting plane; together they cut out the hull), in long
// double.
//   sd(p)        max over facets of n.p - c (<= 0 iff inside);
//   innerMargin  min over the voxel's 8 corners of -sd (convexity: the corners decide);
//   touchDist    a lower bound of the voxel-polytope distance by the separating-axis theorem: the largest
//                gap along the 3 box axes, the facet normals and the cross products of the box axes with
//                every segment between two points (a superset of the edges). It is <= 0 iff they meet (two
//                convex polytopes are disjoint iff one of these axes separates them), so "gap <= 0 =>
//                touched" is exact, and "gap >= 1e-6 => not touched" is the tightness check. A small
//                positive gap says nothing (the distance may be large), so contacts broken by the jitter
//                are checked by samples instead: every voxel holding (within 1e-11) a vertex, a point on a
//                segment between two points, or a point on a facet must be touched.

struct RefPoly {
    std::vector<std::array<L, 3>> pts;
    std::vector<std::array<L, 4>> planes; // unit n, c: n.p <= c inside
    std::vector<std::array<L, 3>> axes;   // unit SAT axes beyond the box's
    L lo[3], hi[3];

    explicit RefPoly(const std::vector<Vec3>& points) {
        for (const Vec3& q : points) pts.push_back({L(q.x), L(q.y), L(q.z)});
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::numeric_limits<L>::infinity();
            hi[a] = -lo[a];
            for (const auto& q : pts) lo[a] = std::min(lo[a], q[a]), hi[a] = std::max(hi[a], q[a]);
        }
        const std::size_t n = pts.size();
        auto sub = [](const std::array<L, 3>& a, const std::array<L, 3>& b) { return std::array<L, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
        auto cross = [](const std::array<L, 3>& a, const std::array<L, 3>& b) {
            return std::array<L, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        };
        auto dot = [](const std::array<L, 3>& a, const std::array<L, 3>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
        L extent = 0;
        for (int a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a]);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j)
                for (std::size_t k = j + 1; k < n; ++k) {
                    auto nn = cross(sub(pts[j], pts[i]), sub(pts[k], pts[i]));
                    const L len = std::sqrt(dot(nn, nn));
                    if (!(len > 1e-12L * extent * extent)) continue;
                    for (L& c : nn) c /= len;
                    const L c0 = dot(nn, pts[i]);
                    L mx = -std::numeric_limits<L>::infinity(), mn = -mx;
                    for (const auto& q : pts) mx = std::max(mx, dot(nn, q) - c0), mn = std::min(mn, dot(nn, q) - c0);
                    const L tol = 1e-15L * (extent + 1);
                    if (mx <= tol) planes.push_back({nn[0], nn[1], nn[2], c0 + std::max(mx, L(0))});
                    else if (mn >= -tol) planes.push_back({-nn[0], -nn[1], -nn[2], -c0 - std::min(mn, L(0))});
                }
        for (const auto& pl : planes) axes.push_back({pl[0], pl[1], pl[2]});
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i + 1; j < n; ++j) {
                const auto e = sub(pts[j], pts[i]);
                for (int a = 0; a < 3; ++a) {
                    std::array<L, 3> u{0, 0, 0};
                    u[a] = 1;
                    auto c = cross(u, e);
                    const L len = std::sqrt(dot(c, c));
                    if (len > 1e-12L * (extent + 1)) axes.push_back({c[0] / len, c[1] / len, c[2] / len});
                }
            }
    }
    L sd(const L p[3]) const {
        L m = -std::numeric_limits<L>::infinity();
        for (const auto& pl : planes) m = std::max(m, pl[0] * p[0] + pl[1] * p[1] + pl[2] * p[2] - pl[3]);
        return m;
    }
    L innerMargin(const IVec3& v) const {
        L m = std::numeric_limits<L>::infinity();
        for (int k = 0; k < 8; ++k) {
            const L p[3] = {L(v.x + (k & 1)), L(v.y + ((k >> 1) & 1)), L(v.z + ((k >> 2) & 1))};
            m = std::min(m, -sd(p));
        }
        return m;
    }
    /// The SAT gap between the polytope and the box [b0, b1].
    L gap(const L b0[3], const L b1[3]) const {
        L g = 0;
        for (int a = 0; a < 3; ++a) g = std::max({g, lo[a] - b1[a], b0[a] - hi[a]});
        if (g > 0) return g;
        for (const auto& u : axes) {
            L pmin = std::numeric_limits<L>::infinity(), pmax = -pmin;
            for (const auto& q : pts) {
                const L d = u[0] * q[0] + u[1] * q[1] + u[2] * q[2];
                pmin = std::min(pmin, d), pmax = std::max(pmax, d);
            }
            L bmin = 0, bmax = 0;
            for (int a = 0; a < 3; ++a) {
                bmin += u[a] * (u[a] >= 0 ? b0[a] : b1[a]);
                bmax += u[a] * (u[a] >= 0 ? b1[a] : b0[a]);
            }
            g = std::max({g, pmin - bmax, bmin - pmax});
        }
        return g;
    }
    L touchDist(const IVec3& v) const {
        const L b0[3] = {L(v.x), L(v.y), L(v.z)}, b1[3] = {L(v.x + 1), L(v.y + 1), L(v.z + 1)};
        return gap(b0, b1);
    }
    bool outsideGrid(IVec3 res) const {
        for (int a = 0; a < 3; ++a)
            if (lo[a] < 0 || hi[a] > res[a]) return true;
        return false;
    }
};

/// checkShape3 for a polytope built from `points` (the oracle's input; `s` is what the library built).
inline std::string checkPolytope3(const Shape<3>& s, const std::vector<Vec3>& points, IVec3 res, Stats& st) {
    const RefPoly ref(points);
    if (ref.planes.size() < 4) return "oracle: fewer than 4 facets";
    Emitted<3> inner(res), touched(res);
    if (std::string e = rasterizeAndCount<3>(s, ref, res, true, st, inner, touched); !e.empty()) return e;
    auto* const fail = &voxelFailure<3>;
    for (int z = 0; z < res.z; ++z)
        for (int y = 0; y < res.y; ++y)
            for (int x = 0; x < res.x; ++x) {
                ++st.voxels;
                const IVec3 v(x, y, z);
                const std::size_t i = linearOf<3>(v, res);
                const bool isInner = inner.hit[i], isTouched = touched.hit[i];
                const L td = ref.touchDist(v), im = ref.innerMargin(v);
                if (isInner && !isTouched) return fail("inner but not touched", v, td, im);
                if (td <= 0 && !isTouched) return fail("touches the polytope but not reported touched", v, td, im);
                if (td >= kTight && isTouched) return fail("misses the polytope by >= 1e-6 but reported touched", v, td, im);
                if (im >= kTight && !isInner) return fail("inside the polytope with margin >= 1e-6 but not inner", v, td, im);
                // Faces snap to voxel boundaries by up to 1e-9 on each of y/z (chords) and x (innerRange).
                if (isInner && im < -2 * kTolInner) return fail("reported inner but a corner is outside the polytope", v, td, im);
                if (im >= 0 && im < kTight) ++st.innerContact;
                if (isTouched && td <= 0) {
                    const L b0[3] = {x + 1e-7L, y + 1e-7L, z + 1e-7L}, b1[3] = {x + 1 - 1e-7L, y + 1 - 1e-7L, z + 1 - 1e-7L};
                    if (ref.gap(b0, b1) > 0) ++st.contact;
                }
            }
    // Samples of the polytope: vertices, points on every segment between two points, points on facets.
    std::vector<std::array<L, 3>> samples = ref.pts;
    const std::size_t n = ref.pts.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j)
            for (int k = 1; k < 8; ++k) {
                const L t = L(k) / 8;
                samples.push_back({ref.pts[i][0] + t * (ref.pts[j][0] - ref.pts[i][0]), ref.pts[i][1] + t * (ref.pts[j][1] - ref.pts[i][1]),
                                   ref.pts[i][2] + t * (ref.pts[j][2] - ref.pts[i][2])});
            }
    for (const auto& pl : ref.planes) {
        std::vector<std::size_t> on;
        for (std::size_t i = 0; i < n; ++i)
            if (std::fabs(pl[0] * ref.pts[i][0] + pl[1] * ref.pts[i][1] + pl[2] * ref.pts[i][2] - pl[3]) < 1e-12L) on.push_back(i);
        for (std::size_t a = 0; a + 2 < on.size(); ++a)
            for (int k = 1; k < 6; ++k)
                for (int m = 1; k + m < 6; ++m) {
                    const auto& A = ref.pts[on[a]];
                    const auto& B = ref.pts[on[a + 1]];
                    const auto& C = ref.pts[on[a + 2]];
                    const L u = L(k) / 6, w = L(m) / 6;
                    samples.push_back({A[0] + u * (B[0] - A[0]) + w * (C[0] - A[0]), A[1] + u * (B[1] - A[1]) + w * (C[1] - A[1]),
                                       A[2] + u * (B[2] - A[2]) + w * (C[2] - A[2])});
                }
    }
    for (const auto& q : samples) {
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(0, int(std::floor(q[a] - kTolSound)));
            hi[a] = std::min(res[a] - 1, int(std::floor(q[a] + kTolSound)));
            if (q[a] + kTolSound < 0 || q[a] - kTolSound > res[a]) lo[a] = 1, hi[a] = 0;
        }
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    const IVec3 v(x, y, z);
                    ++st.sampleChecks;
                    if (!touched.hit[linearOf<3>(v, res)]) return fail("holds a sample point of the polytope but not reported touched", v, ref.touchDist(v), ref.innerMargin(v));
                }
    }
    return "";
}

} // namespace raster_oracle
