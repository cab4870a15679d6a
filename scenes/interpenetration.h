// An exact interpenetration check of a scene's colliders, independent of
// the contact system: every pair of colliders that may touch (their groups
// and masks; a Surface with itself) is tested primitive against primitive,
// by brute force over all pairs (no candidate list, no bounding-volume tree,
// no barrier distance):
//
// - a Plane against every vertex of the other shape: n·x − c > thickness;
// - an edge through a triangle (orientation signs: the segment's ends on
//   both sides of the triangle's plane and the line through the triangle's
//   three edges alike);
// - with a thickness t = t_a + t_b > 0 (spheres, capsules, rods, shells), the
//   closest distance of every vertex–triangle and edge–edge pair and every
//   point (a sphere's centre) to every primitive above t (closed forms of
//   the closest points, Ericson, "Real-Time Collision Detection" §5.1).
//
// Within one Surface the primitive pairs that share a vertex are skipped, and
// so are those the contact system does not separate: within d̂ (the gap) in
// the actor's reference configuration (ContactSystem's rule).
#pragma once

#include <algorithm>
#include <limits>
#include <sstream>
#include <string>

#include <superdex/superdex.h>

namespace superdex::scenes {

class InterpenetrationCheck {
 public:
  explicit InterpenetrationCheck(real activationDistance) : activationDistance_(activationDistance) {}

  /// "" when no two colliders interpenetrate at the scene's current state,
  /// else where the first pair found does.
  std::string Find(Scene const& scene) {
    minGap_ = std::numeric_limits<real>::infinity();
    Gather(scene, now_);
    Rest(scene, now_, rest_);
    for (std::size_t a = 0; a < now_.size(); ++a)
      for (std::size_t b = a; b < now_.size(); ++b) {
        if (!now_[a].collider->MayTouch(*now_[b].collider)) continue;  // the library's filter
        std::string found = CheckPair(now_[a], now_[b], a == b ? &rest_[a] : nullptr);
        if (!found.empty()) return found;
      }
    return {};
  }

  /// The smallest gap (distance less thicknesses; to a plane, signed) over
  /// the pairs the last Find tested where thicknesses or a plane are
  /// involved, of those within the activation distance [m]; +inf when there
  /// were none.
  real GetMinGap() const { return minGap_; }

  /// The distance from p to segment ab (a point where a = b).
  static real PointSegmentDistance(Real3 const& p, Real3 const& a, Real3 const& b) {
    Real3 const ab = b - a;
    real const length2 = ab.squaredNorm();
    real const t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, real(0), real(1)) : 0;
    return (p - (a + t * ab)).norm();
  }

  /// The distance from p to triangle abc: the nearest of its edges, or of
  /// its plane where p lies over its inside (the signs of the edges'
  /// orientations about the normal of its two shortest edges). Unlike a
  /// closest-point method by barycentric differences (Ericson's §5.1.5), it
  /// stays finite on a sliver: a Box face of edges 1e9 m and 0.3 m made
  /// differences of ~1e18 cancel to 0/0 (fuzz_contact).
  static real PointTriangleDistance(Real3 const& p, Real3 const& a, Real3 const& b, Real3 const& c) {
    real distance = std::min({PointSegmentDistance(p, a, b), PointSegmentDistance(p, b, c),
                              PointSegmentDistance(p, c, a)});
    std::array<Real3, 3> const corner{a, b, c};
    std::array<Real3, 3> const edge{b - a, c - b, a - c};  // edge k leaves corner k
    // the corner between the two shortest edges: the normal's best cross product
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (std::max(edge[i].squaredNorm(), edge[(i + 2) % 3].squaredNorm()) <
          std::max(edge[k].squaredNorm(), edge[(k + 2) % 3].squaredNorm()))
        k = i;
    Real3 normal = edge[(k + 2) % 3].cross(edge[k]);
    if (!(normal.squaredNorm() > 0)) return distance;  // a degenerate triangle is its edges
    normal.normalize();
    for (int i = 0; i < 3; ++i)
      if (edge[i].cross(p - corner[i]).dot(normal) < 0) return distance;
    return std::min(distance, std::abs(normal.dot(p - a)));
  }

 private:
  struct Shape {
    Collider const* collider = nullptr;
    DynamicArray<Real3> x;
  };

  static void Gather(Scene const& scene, DynamicArray<Shape>& shapes) {
    shapes.resize(scene.GetNumColliders());
    int index = 0;
    for (int id = 0; index < scene.GetNumColliders(); ++id) {
      Collider const* c = scene.GetCollider(id);
      if (!c) continue;
      shapes[index].collider = c;
      c->GetWorldVertices(shapes[index].x);
      ++index;
    }
  }

  /// A Surface's shape in its actor's reference configuration (the rest
  /// shape of self contact); other colliders as they are.
  static void Rest(Scene const& scene, DynamicArray<Shape> const& now, DynamicArray<Shape>& rest) {
    rest = now;
    for (Shape& s : rest) {
      if (s.collider->GetShape() != ShapeType::Surface) continue;
      Actor const* actor = scene.GetActor(s.collider->GetActor());
      if (auto const* d = dynamic_cast<DeformableActor const*>(actor))
        for (std::size_t i = 0; i < s.x.size(); ++i) s.x[i] = d->GetNodeReferencePosition(static_cast<int>(i));
      else if (auto const* r = dynamic_cast<RodActor const*>(actor))
        for (std::size_t i = 0; i < s.x.size(); ++i) s.x[i] = r->GetNodeReferencePosition(static_cast<int>(i));
    }
  }


  static real Orient(Real3 const& a, Real3 const& b, Real3 const& c, Real3 const& d) {
    return (b - a).cross(c - a).dot(d - a);
  }

  /// Whether segment pq meets triangle abc (touching counts). Volumes below
  /// round-off of the primitives' size count as zero (a flat sheet is
  /// coplanar, not crossing by noise); an end on the plane, or a coplanar
  /// segment, meets the triangle where their distance is zero.
  static bool SegmentMeetsTriangle(Real3 const& p, Real3 const& q, Real3 const& a, Real3 const& b,
                                   Real3 const& c) {
    real const size = std::max({(q - p).norm(), (b - a).norm(), (c - b).norm(), (a - c).norm()});
    real const eps = 64 * std::numeric_limits<real>::epsilon() * size * size * size;
    auto sign = [&](real v) { return v > eps ? 1 : v < -eps ? -1 : 0; };
    int const sp = sign(Orient(a, b, c, p)), sq = sign(Orient(a, b, c, q));
    if (sp * sq > 0) return false;
    if (sp == 0 || sq == 0) {
      real const touch = 64 * std::numeric_limits<real>::epsilon() * size;
      real d = std::min(sp == 0 ? PointTriangleDistance(p, a, b, c) : real(1e300),
                        sq == 0 ? PointTriangleDistance(q, a, b, c) : real(1e300));
      if (sp == 0 && sq == 0)
        d = std::min({d, SegmentDistance(p, q, a, b), SegmentDistance(p, q, b, c), SegmentDistance(p, q, c, a)});
      return d <= touch;
    }
    int const o1 = sign(Orient(p, q, a, b)), o2 = sign(Orient(p, q, b, c)), o3 = sign(Orient(p, q, c, a));
    return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
  }

  /// The distance between segments p1q1 and p2q2 (Ericson's, §5.1.9; a
  /// segment of zero length is its point).
  static real SegmentDistance(Real3 const& p1, Real3 const& q1, Real3 const& p2, Real3 const& q2) {
    Real3 const d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    real const a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    real s = 0, t = 0;
    if (a == 0 && e == 0) return r.norm();
    if (a == 0) {
      t = std::clamp(f / e, real(0), real(1));
    } else {
      real const c = d1.dot(r);
      if (e == 0) {
        s = std::clamp(-c / a, real(0), real(1));
      } else {
        real const b = d1.dot(d2), denom = a * e - b * b;
        s = denom != 0 ? std::clamp((b * f - c * e) / denom, real(0), real(1)) : 0;
        t = (b * s + f) / e;
        if (t < 0) {
          t = 0;
          s = std::clamp(-c / a, real(0), real(1));
        } else if (t > 1) {
          t = 1;
          s = std::clamp((b - c) / a, real(0), real(1));
        }
      }
    }
    return ((p1 + d1 * s) - (p2 + d2 * t)).norm();
  }

  template <int N>
  static bool Shares(std::array<int, N> const& p, int const* q, int m) {
    for (int i : p)
      for (int k = 0; k < m; ++k)
        if (i == q[k]) return true;
    return false;
  }

  struct Box {
    Real3 lo, hi;
    bool Near(Box const& o, real margin) const {
      return ((lo.array() - margin) <= o.hi.array()).all() && ((o.lo.array() - margin) <= hi.array()).all();
    }
  };
  template <std::size_t N>
  static Box BoxOf(DynamicArray<Real3> const& x, std::array<int, N> const& v) {
    Box box{x[v[0]], x[v[0]]};
    for (int i : v) {
      box.lo = box.lo.cwiseMin(x[i]);
      box.hi = box.hi.cwiseMax(x[i]);
    }
    return box;
  }

  /// The vertices of c that lie on a primitive (a solid's interior nodes do not).
  static DynamicArray<char> OnPrimitive(Collider const& c, int numVertices) {
    DynamicArray<char> on(numVertices, 0);
    for (auto const& e : c.GetEdges()) on[e[0]] = on[e[1]] = 1;
    for (int i = 0; i < numVertices; ++i)
      if (c.IsPoint(i)) on[i] = 1;
    return on;
  }

  std::string Report(Shape const& a, Shape const& b, std::string const& what) const {
    std::ostringstream out;
    out << "colliders " << a.collider->GetId() << " (" << ToString(a.collider->GetShape()) << ") and "
        << b.collider->GetId() << " (" << ToString(b.collider->GetShape()) << "): " << what;
    return out.str();
  }

  std::string CheckPair(Shape const& a, Shape const& b, Shape const* rest) {
    Collider const& ca = *a.collider;
    Collider const& cb = *b.collider;
    real const t = ca.GetThickness() + cb.GetThickness();
    if (ca.GetShape() == ShapeType::Plane || cb.GetShape() == ShapeType::Plane) {
      bool const aPlane = ca.GetShape() == ShapeType::Plane;
      Shape const& body = aPlane ? b : a;
      Collider const& plane = aPlane ? ca : cb;
      DynamicArray<char> const on = OnPrimitive(*body.collider, static_cast<int>(body.x.size()));
      for (std::size_t i = 0; i < body.x.size(); ++i) {
        if (!on[i]) continue;
        real const gap = plane.GetPlaneNormal().dot(body.x[i]) - plane.GetPlaneOffset() - t;
        minGap_ = std::min(minGap_, gap);
        if (gap <= 0) {
          std::ostringstream what;
          what << "vertex " << i << " at " << body.x[i].transpose() << " is " << -gap << " m through the plane";
          return Report(a, b, what.str());
        }
      }
      return {};
    }
    // the pairs that are too close to separate in the rest shape (self only)
    auto restClose = [&](real restDistance) { return rest && restDistance - t <= activationDistance_; };

    // edges through triangles, both ways
    auto crossings = [&](Shape const& s, Shape const& o) -> std::string {
      for (std::size_t e = 0; e < s.collider->GetEdges().size(); ++e) {
        auto const edge = s.collider->GetEdges()[e];
        Box const eb = BoxOf(s.x, edge);
        for (std::size_t f = 0; f < o.collider->GetTriangles().size(); ++f) {
          auto const tri = o.collider->GetTriangles()[f];
          if (rest && Shares<2>(edge, tri.data(), 3)) continue;
          if (!eb.Near(BoxOf(o.x, tri), 0)) continue;
          if (!SegmentMeetsTriangle(s.x[edge[0]], s.x[edge[1]], o.x[tri[0]], o.x[tri[1]], o.x[tri[2]])) continue;
          if (rest && restClose(std::min({SegmentDistance(rest->x[edge[0]], rest->x[edge[1]], rest->x[tri[0]],
                                                          rest->x[tri[1]]),
                                          SegmentDistance(rest->x[edge[0]], rest->x[edge[1]], rest->x[tri[1]],
                                                          rest->x[tri[2]]),
                                          SegmentDistance(rest->x[edge[0]], rest->x[edge[1]], rest->x[tri[2]],
                                                          rest->x[tri[0]])})))
            continue;
          std::ostringstream what;
          what << "edge " << e << " (" << s.x[edge[0]].transpose() << " to " << s.x[edge[1]].transpose()
               << ") of collider " << s.collider->GetId() << " passes through triangle " << f << " of collider "
               << o.collider->GetId();
          return Report(a, b, what.str());
        }
      }
      return {};
    };
    if (std::string found = crossings(a, b); !found.empty()) return found;
    if (!rest)
      if (std::string found = crossings(b, a); !found.empty()) return found;
    if (t <= 0) return {};

    // thick primitives: vertex–triangle, edge–edge and point–primitive distances
    auto tooClose = [&](real distance, std::string const& what) -> std::string {
      minGap_ = std::min(minGap_, distance - t);
      if (distance - t > 0) return {};
      std::ostringstream out;
      out << what << " are " << distance << " m apart, within the thicknesses " << t << " m";
      return Report(a, b, out.str());
    };
    auto vertexTriangles = [&](Shape const& s, Shape const& o) -> std::string {
      DynamicArray<char> const on = OnPrimitive(*s.collider, static_cast<int>(s.x.size()));
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!on[i]) continue;
        Box const vb{s.x[i], s.x[i]};
        int const vi = static_cast<int>(i);
        for (std::size_t f = 0; f < o.collider->GetTriangles().size(); ++f) {
          auto const tri = o.collider->GetTriangles()[f];
          if (rest && Shares<3>(tri, &vi, 1)) continue;
          if (!vb.Near(BoxOf(o.x, tri), t + activationDistance_)) continue;
          real const d = PointTriangleDistance(s.x[i], o.x[tri[0]], o.x[tri[1]], o.x[tri[2]]);
          if (d > t + activationDistance_) continue;  // (farther: no gap to record)
          if (rest && restClose(PointTriangleDistance(rest->x[i], rest->x[tri[0]], rest->x[tri[1]], rest->x[tri[2]])))
            continue;
          if (std::string found = tooClose(d, "vertex " + std::to_string(i) + " and triangle " + std::to_string(f));
              !found.empty())
            return found;
        }
      }
      return {};
    };
    if (std::string found = vertexTriangles(a, b); !found.empty()) return found;
    if (!rest)
      if (std::string found = vertexTriangles(b, a); !found.empty()) return found;
    for (std::size_t e = 0; e < ca.GetEdges().size(); ++e) {
      auto const ea = ca.GetEdges()[e];
      Box const box = BoxOf(a.x, ea);
      for (std::size_t g = rest ? e + 1 : 0; g < cb.GetEdges().size(); ++g) {
        auto const eb = cb.GetEdges()[g];
        if (rest && Shares<2>(ea, eb.data(), 2)) continue;
        if (!box.Near(BoxOf(b.x, eb), t + activationDistance_)) continue;
        real const d = SegmentDistance(a.x[ea[0]], a.x[ea[1]], b.x[eb[0]], b.x[eb[1]]);
        if (d > t + activationDistance_) continue;  // (farther: no gap to record)
        if (rest && restClose(SegmentDistance(rest->x[ea[0]], rest->x[ea[1]], rest->x[eb[0]], rest->x[eb[1]])))
          continue;
        if (std::string found = tooClose(d, "edges " + std::to_string(e) + " and " + std::to_string(g));
            !found.empty())
          return found;
      }
    }
    // points (sphere centres) against every vertex and edge of the other
    auto points = [&](Shape const& s, Shape const& o) -> std::string {
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        if (!s.collider->IsPoint(static_cast<int>(i))) continue;
        DynamicArray<char> const on = OnPrimitive(*o.collider, static_cast<int>(o.x.size()));
        for (std::size_t j = 0; j < o.x.size(); ++j)
          if (on[j] && (&s != &o || i != j))
            if (std::string found = tooClose((s.x[i] - o.x[j]).norm(), "point " + std::to_string(i) +
                                                                            " and vertex " + std::to_string(j));
                !found.empty())
              return found;
        for (std::size_t g = 0; g < o.collider->GetEdges().size(); ++g) {
          auto const eb = o.collider->GetEdges()[g];
          if (std::string found = tooClose(SegmentDistance(s.x[i], s.x[i], o.x[eb[0]], o.x[eb[1]]),
                                           "point " + std::to_string(i) + " and edge " + std::to_string(g));
              !found.empty())
            return found;
        }
      }
      return {};
    };
    if (std::string found = points(a, b); !found.empty()) return found;
    if (!rest)
      if (std::string found = points(b, a); !found.empty()) return found;
    return {};
  }

  real activationDistance_ = 0;
  real minGap_ = std::numeric_limits<real>::infinity();
  DynamicArray<Shape> rest_, now_;
};

}  // namespace superdex::scenes
