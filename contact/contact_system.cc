#include <superdex/contact/contact_system.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include <superdex/actors/deformable_actor.h>
#include <superdex/actors/rod_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/contact/barrier.h>
#include <superdex/contact/bvh.h>
#include <superdex/contact/ccd.h>
#include <superdex/contact/distance.h>
#include <superdex/core/so3.h>
#include <superdex/core/stopwatch.h>
#include <superdex/core/validate.h>

namespace superdex {

std::string_view ToString(ShapeType type) {
  switch (type) {
    case ShapeType::Plane: return "Plane";
    case ShapeType::Sphere: return "Sphere";
    case ShapeType::Box: return "Box";
    case ShapeType::Capsule: return "Capsule";
    case ShapeType::TriangleMesh: return "TriangleMesh";
    case ShapeType::Surface: return "Surface";
  }
  return "unknown";
}

namespace internal {

bool ValidateContactParams(ContactParams const& params, Error& error) {
  return CheckPositive(params.activationDistance, "contact.activationDistance", error) &&
         CheckPositive(params.stiffness, "contact.stiffness", error) &&
         CheckPositive(params.frictionRampWidth, "contact.frictionRampWidth", error) &&
         CheckIntInRange(params.ccdMaxIterations, 1, 100'000'000, "contact.ccdMaxIterations", error);
}

namespace {

using Vector12 = Eigen::Matrix<real, 12, 1>;
using Matrix12 = Eigen::Matrix<real, 12, 12>;

/// Edges of a triangle list, each once (sorted vertex pair), in a fixed order.
DynamicArray<std::array<int, 2>> EdgesOf(DynamicArray<std::array<int, 3>> const& triangles) {
  DynamicArray<std::array<int, 2>> edges;
  for (auto const& t : triangles)
    for (int k = 0; k < 3; ++k) {
      int a = t[k], b = t[(k + 1) % 3];
      if (a > b) std::swap(a, b);
      edges.push_back({a, b});
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

/// The boundary triangles of a tetrahedral mesh (faces of one tet only),
/// oriented outwards, in a fixed order.
DynamicArray<std::array<int, 3>> BoundaryOf(DynamicArray<std::array<int, 4>> const& tets) {
  struct Face {
    std::array<int, 3> sorted, oriented;
  };
  DynamicArray<Face> faces;
  for (auto const& t : tets) {
    // faces opposite each vertex, oriented outwards for a positive tet
    std::array<std::array<int, 3>, 4> const f{{{t[1], t[3], t[2]}, {t[0], t[2], t[3]}, {t[0], t[3], t[1]},
                                               {t[0], t[1], t[2]}}};
    for (auto const& o : f) {
      std::array<int, 3> s = o;
      std::sort(s.begin(), s.end());
      faces.push_back({s, o});
    }
  }
  std::sort(faces.begin(), faces.end(), [](Face const& a, Face const& b) { return a.sorted < b.sorted; });
  DynamicArray<std::array<int, 3>> boundary;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].sorted == faces[i].sorted) ++j;
    if (j - i == 1) boundary.push_back(faces[i].oriented);
    i = j;
  }
  return boundary;
}

std::uint64_t PairKey(int kind, int body, int obstacle, std::array<int, 4> const& v) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::uint64_t x) {
    h ^= x;
    h *= 1099511628211ull;
  };
  mix(static_cast<std::uint64_t>(kind));
  mix(static_cast<std::uint64_t>(body));
  mix(static_cast<std::uint64_t>(obstacle));
  for (int i : v) mix(static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)));
  return h;
}

/// The index of edge (a, b) in `edges` (sorted, as EdgesOf makes them).
int EdgeIndex(DynamicArray<std::array<int, 2>> const& edges, int a, int b) {
  std::array<int, 2> const key{std::min(a, b), std::max(a, b)};
  return static_cast<int>(std::lower_bound(edges.begin(), edges.end(), key) - edges.begin());
}

/// The box of a primitive's vertices, inflated by `margin`.
contact::Aabb BoxOf(DynamicArray<Real3> const& x, std::initializer_list<int> vertices, real margin) {
  contact::Aabb box{x[*vertices.begin()], x[*vertices.begin()]};
  for (int i : vertices) {
    box.lower = box.lower.cwiseMin(x[i]);
    box.upper = box.upper.cwiseMax(x[i]);
  }
  box.lower.array() -= margin;
  box.upper.array() += margin;
  return box;
}

contact::Aabb Merge(contact::Aabb const& a, contact::Aabb const& b) {
  return {a.lower.cwiseMin(b.lower), a.upper.cwiseMax(b.upper)};
}

real TriangleArea(Real3 const& a, Real3 const& b, Real3 const& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

/// Within the contact geometry's range, kMaxContactCoordinate [m].
template <class Value>
bool CheckInRange(Value const& value, std::string_view field, Error& error) {
  return CheckMagnitude(value, kMaxContactCoordinate, field, error);
}

/// Every world vertex of `c` within range (a body far away, or an obstacle
/// moved there); `what` names the collider.
bool CheckWorldInRange(Collider const& c, std::string const& what, Error& error) {
  DynamicArray<Real3> world;
  c.GetWorldVertices(world);
  for (std::size_t i = 0; i < world.size(); ++i)
    if (!CheckInRange(world[i], what + " vertex " + std::to_string(i) + " (world)", error)) return false;
  return true;
}

}  // namespace

// ---- colliders ----

Collider* ContactSystem::Add(ColliderParams const& p, RigidActor* rigid, NodalActor* nodal,
                             ArticulatedActor* articulated, Error& error) {
  if (!CheckFinite(p.position, "position", error) || !CheckUnitQuat(p.rotation, "rotation", error) ||
      !CheckNonNegative(p.friction, "friction", error) || !CheckNonNegative(p.thickness, "thickness", error) ||
      !CheckNonNegative(p.radius, "radius", error) || !CheckInRange(p.position, "position", error))
    return nullptr;
  if (articulated) {
    if (p.link < 0 || p.link >= articulated->GetNumLinks()) {
      error.Set(ErrorCode::InvalidArgument, "link must name a link of the articulated actor, in [0, " +
                                                std::to_string(articulated->GetNumLinks()) + "), got " +
                                                std::to_string(p.link));
      return nullptr;
    }
    if (int const dofs = static_cast<int>(articulated->GetLinkPath(p.link).dofs.size()); dofs > kMaxLinkPathDofs) {
      error.Set(ErrorCode::NotSupported, "link: a collider's link moves with at most " +
                                             std::to_string(kMaxLinkPathDofs) + " joint DoFs, link " +
                                             std::to_string(p.link) + " with " + std::to_string(dofs));
      return nullptr;
    }
  } else if (p.link != -1) {
    error.Set(ErrorCode::InvalidArgument,
              "link: only a collider of an articulated actor names a link (-1 otherwise), got " + std::to_string(p.link));
    return nullptr;
  }
  if (p.shape == ShapeType::Surface && !nodal) {
    error.Set(ErrorCode::InvalidArgument,
              "shape: Surface needs a deformable or rod actor (the actor's own surface)");
    return nullptr;
  }
  if (nodal && p.shape != ShapeType::Surface) {
    error.Set(ErrorCode::InvalidArgument, "shape: a deformable or rod actor's collider is its Surface, got " +
                                              std::string(ToString(p.shape)));
    return nullptr;
  }
  if (p.shape == ShapeType::Plane && (rigid || nodal || articulated)) {
    error.Set(ErrorCode::InvalidArgument, "shape: a Plane is a static obstacle (actor must be null)");
    return nullptr;
  }
  auto c = std::unique_ptr<Collider>(new Collider());
  c->shape_ = p.shape;
  c->friction_ = p.friction;
  c->thickness_ = p.thickness;
  c->group_ = p.group;
  c->mask_ = p.mask;
  c->rigid_ = rigid;
  c->nodal_ = nodal;
  c->articulated_ = articulated;
  if (rigid) c->actor_ = rigid->GetHandle();
  if (nodal) c->actor_ = nodal->GetHandle();
  if (articulated) {
    c->actor_ = articulated->GetHandle();
    c->path_ = articulated->GetLinkPath(p.link);
  }
  c->system_ = this;
  c->created_ = c->start_ = c->target_ = c->now_ = c->stageStart_ = c->stageTarget_ = {p.position, p.rotation};
  DynamicArray<std::array<int, 3>> triangles;
  // the shape's own range: its world vertices and its thickness (a sphere's
  // or capsule's radius, a rod Surface's the rod's radius)
  if (!MakeShape(p, *c, triangles, error) || !SetPrimitives(*c, std::move(triangles), error) ||
      !CheckWorldInRange(*c, "CreateCollider: the " + std::string(ToString(p.shape)) + "'s", error) ||
      !CheckInRange(c->thickness_, "thickness", error))
    return nullptr;
  if (obstacleOnlyRanks_ > 1) {
    // across ranks a pair of two bodies (or of one body with itself) would
    // join blocks the pattern lacks, which cannot grow there yet
    std::string const across = "CreateCollider: on a scene across " + std::to_string(obstacleOnlyRanks_) +
                               " MPI ranks only contact with static and kinematic obstacles is supported: ";
    if (c->MayTouch(*c)) {
      error.Set(ErrorCode::NotSupported,
                across + "this Surface would touch itself (its group is in its mask: give it a mask without it)");
      return nullptr;
    }
    for (auto const& other : colliders_)
      if (other->Moves() && c->MayTouch(*other)) {
        error.Set(ErrorCode::NotSupported, across + "it may touch collider " + std::to_string(other->id_) + " (" +
                                               std::string(ToString(other->shape_)) +
                                               ", on a body): give them groups and masks that exclude each other");
        return nullptr;
      }
  }
  c->id_ = nextId_++;
  colliders_.push_back(std::move(c));
  trees_.clear();
  if (!CheckSeparated(static_cast<int>(colliders_.size()) - 1, "CreateCollider", error)) {
    colliders_.pop_back();
    --nextId_;
    PrepareVertices();
    return nullptr;
  }
  return colliders_.back().get();
}

bool ContactSystem::MakeShape(ColliderParams const& p, Collider& c, DynamicArray<std::array<int, 3>>& triangles,
                              Error& error) {
  Real33 const rotation = p.rotation.toRotationMatrix();
  auto place = [&](Real3 const& local) {
    Collider::Vertex v;
    v.local = p.position + rotation * local;  // the body frame, or world for an obstacle
    c.local_.push_back(v);
    c.shapeVertices_.push_back(local);
  };
  switch (p.shape) {
    case ShapeType::Plane:
      if (!CheckFinite(p.normal, "normal", error)) return false;
      if (!(p.normal.norm() > 1e-12)) {
        error.Set(ErrorCode::InvalidArgument, "normal: must be non-zero, got " + Format(p.normal));
        return false;
      }
      c.shapeNormal_ = p.normal;
      c.planeNormal_ = (p.rotation * c.shapeNormal_).normalized();
      c.planeOffset_ = c.planeNormal_.dot(p.position);
      return true;
    case ShapeType::Sphere:
      if (!CheckPositive(p.radius, "radius", error)) return false;
      c.thickness_ = p.radius;
      place(Real3::Zero());
      return true;
    case ShapeType::Capsule:
      if (!CheckPositive(p.radius, "radius", error) || !CheckPositive(p.halfLength, "halfLength", error) ||
          !CheckInRange(p.halfLength, "halfLength", error))
        return false;
      c.thickness_ = p.radius;
      place(Real3(0, 0, -p.halfLength));
      place(Real3(0, 0, p.halfLength));
      c.edges_.push_back({0, 1});
      return true;
    case ShapeType::Box: {
      if (!CheckPositive(p.halfExtents, "halfExtents", error) || !CheckInRange(p.halfExtents, "halfExtents", error))
        return false;
      Real3 const e = p.halfExtents;
      for (int i = 0; i < 8; ++i) place(Real3((i & 1) ? e.x() : -e.x(), (i & 2) ? e.y() : -e.y(), (i & 4) ? e.z() : -e.z()));
      // two outward triangles per face
      triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
      return true;
    }
    case ShapeType::TriangleMesh:
      if (p.vertices.empty() || p.triangles.empty()) {
        error.Set(ErrorCode::InvalidArgument, "vertices, triangles: a TriangleMesh needs both, got " +
                                                  std::to_string(p.vertices.size()) + " vertices and " +
                                                  std::to_string(p.triangles.size()) + " triangles");
        return false;
      }
      for (std::size_t i = 0; i < p.vertices.size(); ++i) {
        if (!CheckInRange(p.vertices[i], "vertices[" + std::to_string(i) + "]", error)) return false;
        place(p.vertices[i]);
      }
      triangles = p.triangles;
      return true;
    case ShapeType::Surface: {
      NodalActor const& nodal = *c.nodal_;
      if (nodal.GetType() == ActorType::Rod) {
        c.thickness_ = p.radius > 0 ? p.radius : static_cast<RodActor const&>(nodal).GetRadius();
        for (int e = 0; e + 1 < nodal.GetNumNodes(); ++e) c.edges_.push_back({e, e + 1});
      } else {
        auto const& body = static_cast<DeformableActor const&>(nodal);
        triangles = BoundaryOf(body.GetTetrahedra());
        triangles.insert(triangles.end(), body.GetTriangles().begin(), body.GetTriangles().end());
      }
      // every node is a vertex; a solid's interior nodes are on no
      // primitive, stand for no area and are never in a candidate
      for (int i = 0; i < nodal.GetNumNodes(); ++i) {
        Collider::Vertex v;
        v.node = i;
        c.local_.push_back(v);
      }
      return true;
    }
  }
  error.Set(ErrorCode::InvalidArgument,
            "shape: must be a ShapeType, got the value " + std::to_string(static_cast<int>(p.shape)));
  return false;
}

bool ContactSystem::SetPrimitives(Collider& c, DynamicArray<std::array<int, 3>> triangles, Error& error) const {
  int const n = static_cast<int>(c.local_.size());
  // a body's primitives are weighed (and checked) in its rest shape, so that
  // a collider made on a deformed body, or a scene restarted from a deformed
  // state, has the same incremental potential as one made at rest
  auto at = [&](int i) {
    return c.local_[i].node >= 0 ? c.nodal_->GetNodeReferencePosition(c.local_[i].node) : c.local_[i].local;
  };
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    auto const& tri = triangles[t];
    for (int i : tri)
      if (i < 0 || i >= n) {
        error.Set(ErrorCode::InvalidArgument, "triangles[" + std::to_string(t) + "]: vertex index " +
                                                  std::to_string(i) + " out of range [0, " + std::to_string(n) +
                                                  ")");
        return false;
      }
    if (!(TriangleArea(at(tri[0]), at(tri[1]), at(tri[2])) > 0)) {
      error.Set(ErrorCode::InvalidArgument, "triangles[" + std::to_string(t) + "]: degenerate triangle (zero area)");
      return false;
    }
  }
  c.triangles_ = std::move(triangles);
  if (!c.triangles_.empty()) c.edges_ = EdgesOf(c.triangles_);
  // the area each primitive stands for: a third of each adjacent triangle
  // for a mesh's vertices and edges; a free segment's length times its
  // diameter (half to each vertex); a free point the disc of its radius
  c.vertexArea_.assign(n, 0);
  c.edgeArea_.assign(c.edges_.size(), 0);
  c.freeVertex_.assign(n, 1);
  c.freeEdge_.assign(c.edges_.size(), c.triangles_.empty() ? 1 : 0);
  for (auto const& tri : c.triangles_) {
    real const area = TriangleArea(at(tri[0]), at(tri[1]), at(tri[2]));
    for (int k = 0; k < 3; ++k) {
      c.vertexArea_[tri[k]] += area / 3;
      c.edgeArea_[EdgeIndex(c.edges_, tri[k], tri[(k + 1) % 3])] += area / 3;
    }
  }
  for (std::size_t e = 0; e < c.edges_.size(); ++e) {
    auto const [a, b] = c.edges_[e];
    c.freeVertex_[a] = c.freeVertex_[b] = 0;
    if (!c.freeEdge_[e]) continue;
    real const length = (at(b) - at(a)).norm();
    c.edgeArea_[e] = 2 * c.thickness_ * length;
    c.vertexArea_[a] += c.thickness_ * length;
    c.vertexArea_[b] += c.thickness_ * length;
  }
  for (int i = 0; i < n; ++i)
    if (c.freeVertex_[i] && c.nodal_ == nullptr) c.vertexArea_[i] = M_PI * c.thickness_ * c.thickness_;
  // every primitive's weight a normal number: a pair of weight 0 exerts no
  // barrier (a Capsule 1e-323 m long, its length squared underflowing, was
  // invisible to contact and passed through another)
  auto tooSmall = [&](std::string const& primitive, real weight) {
    char const* fields = c.shape_ == ShapeType::Sphere    ? "radius"
                         : c.shape_ == ShapeType::Capsule ? "radius, halfLength"
                         : c.shape_ == ShapeType::Box     ? "halfExtents, thickness"
                         : c.shape_ == ShapeType::Surface ? "the actor's nodes, thickness"
                                                          : "vertices, thickness";
    error.Set(ErrorCode::InvalidArgument, std::string(fields) + ": the " + std::string(ToString(c.shape_)) +
                                              " is too small to touch anything: the area its " + primitive +
                                              " stands for is " + Format(weight) +
                                              " m^2, below the smallest normal double");
    return false;
  };
  for (std::size_t e = 0; e < c.edges_.size(); ++e)
    if (!std::isnormal(c.edgeArea_[e])) return tooSmall("edge " + std::to_string(e), c.edgeArea_[e]);
  for (int i = 0; i < n; ++i) {
    bool const used = !c.freeVertex_[i] || c.nodal_ == nullptr;  // on a primitive, or a point
    if (used && !std::isnormal(c.vertexArea_[i])) return tooSmall("vertex " + std::to_string(i), c.vertexArea_[i]);
  }
  return true;
}

bool ContactSystem::CheckSeparated(int index, std::string const& what, Error& error) {
  PrepareVertices();
  bound_.assign(x_.size(), 0);
  vertexSelfBound_.assign(x_.size(), 0);
  pairs_.clear();
  ++treeStamp_;
  for (int other = 0; other < static_cast<int>(colliders_.size()); ++other) {
    if (other == index) continue;
    if (MayTouch(index, other)) AddPairs(index, other);
    if (MayTouch(other, index)) AddPairs(other, index);
  }
  if (!CheckNoCrossing(index, what, error)) {
    pairs_.clear();
    return false;
  }
  for (Pair const& pair : pairs_) {
    real const gap = Gap(pair, x_);
    if (gap > 0) continue;
    Collider const& body = *colliders_[pair.body];
    Collider const& obstacle = *colliders_[pair.obstacle];
    error.Set(ErrorCode::InvalidArgument,
              what + ": collider " + std::to_string(body.id_) + " (" + std::string(ToString(body.shape_)) +
                  ") intersects collider " + std::to_string(obstacle.id_) + " (" +
                  std::string(ToString(obstacle.shape_)) + ") at " + Format(x_[pair.v[0]]) + " (gap " +
                  Format(gap) + " m, thicknesses included): colliders must start apart");
    pairs_.clear();
    return false;
  }
  pairs_.clear();
  return true;
}

bool ContactSystem::CheckNoCrossing(int index, std::string const& what, Error& error) {
  // an edge of one collider through a triangle of the other, both ways:
  // shapes that overlap deeply have no primitives within d̂ of each other
  for (int other = 0; other < static_cast<int>(colliders_.size()); ++other) {
    if (other == index || !(MayTouch(index, other) || MayTouch(other, index))) continue;
    for (int side = 0; side < 2; ++side) {
      int const ei = side == 0 ? index : other, ti = side == 0 ? other : index;
      Collider const& ce = *colliders_[ei];
      Collider const& ct = *colliders_[ti];
      if (ce.edges_.empty() || ct.triangles_.empty()) continue;
      int const fe = firstVertex_[ei], ft = firstVertex_[ti];
      boxScratch_.clear();
      for (auto const& e : ce.edges_) boxScratch_.push_back(BoxOf(x_, {fe + e[0], fe + e[1]}, 0));
      TreesOf(ti).triangles.FindPairsWith(boxScratch_, pairScratch_);
      for (auto [t, e] : pairScratch_) {
        auto const& edge = ce.edges_[e];
        auto const& tri = ct.triangles_[t];
        Real3 const& s0 = x_[fe + edge[0]];
        Real3 const& s1 = x_[fe + edge[1]];
        if (!contact::SegmentMeetsTriangle(s0, s1, x_[ft + tri[0]], x_[ft + tri[1]], x_[ft + tri[2]])) continue;
        error.Set(ErrorCode::InvalidArgument,
                  what + ": collider " + std::to_string(colliders_[index]->id_) +
                      " (" + std::string(ToString(colliders_[index]->shape_)) + ") intersects collider " +
                      std::to_string(colliders_[other]->id_) + " (" + std::string(ToString(colliders_[other]->shape_)) +
                      "): an edge of collider " + std::to_string(ce.id_) + " from " + Format(s0) + " to " +
                      Format(s1) + " passes through a triangle of collider " + std::to_string(ct.id_) +
                      "; colliders must start apart");
        return false;
      }
    }
  }
  return true;
}

void ContactSystem::PrepareVertices() {
  firstVertex_.assign(colliders_.size() + 1, 0);
  for (std::size_t c = 0; c < colliders_.size(); ++c)
    firstVertex_[c + 1] = firstVertex_[c] + static_cast<int>(colliders_[c]->local_.size());
  int const numVertices = firstVertex_.back();
  x_.resize(numVertices);
  displacement_.resize(numVertices);
  vertexFraction_.resize(numVertices);  // (LimitStepPerDof assigns without allocating)
  UpdatePositions(x_);
  x0_ = x_;
  boundCenter_ = x_;
}

void ContactSystem::RemoveActor(ActorHandle actor) {
  std::erase_if(colliders_, [&](std::unique_ptr<Collider> const& c) { return !actor.IsNull() && c->actor_ == actor; });
  pairs_.clear();
  trees_.clear();
  PrepareVertices();
}

Collider const* ContactSystem::GetCollider(int id) const {
  for (auto const& c : colliders_)
    if (c->id_ == id) return c.get();
  return nullptr;
}

bool ContactSystem::MayTouch(int a, int b) const {
  // each unordered pair once: a body (side A) against an obstacle, or
  // against a body of a later collider (a self pair: a == b)
  Collider const& ca = *colliders_[a];
  Collider const& cb = *colliders_[b];
  if (a != b && (!ca.Moves() || (cb.Moves() && b <= a))) return false;
  return ca.MayTouch(cb);
}

// ---- a static obstacle's motion ----

namespace {
/// The checks SetTransform and SetTargetTransform share.
bool CheckObstaclePose(Collider const& c, std::string const& call, Real3 const& position, Quat const& rotation,
                       Error& error) {
  if (c.Moves()) {
    error.Set(ErrorCode::InvalidArgument, call + ": collider " + std::to_string(c.GetId()) + " (" +
                                              std::string(ToString(c.GetShape())) +
                                              ") is carried by an actor; only a static obstacle (actor null) "
                                              "is moved this way (move its actor)");
    return false;
  }
  return CheckInRange(position, call + ": position", error) && CheckUnitQuat(rotation, "rotation", error);
}
}  // namespace

}  // namespace internal

bool Collider::MayTouch(Collider const& other) const {
  if (&other == this) return shape_ == ShapeType::Surface && (group_ & mask_) != 0;  // self contact
  if (!Moves() && !other.Moves()) return false;
  if (Moves() && other.Moves() && actor_ == other.actor_) {
    // one actor's colliders: only two links of a mechanism that no joint joins
    if (!articulated_ || !other.articulated_) return false;
    int const a = path_.link, b = other.path_.link;
    if (a == b || articulated_->GetParent(a) == b || articulated_->GetParent(b) == a) return false;
  }
  return (group_ & other.mask_) && (other.group_ & mask_);
}

void Collider::Place(Pose const& p) {
  if (now_ == p) return;
  now_ = p;
  ++poseVersion_;
  if (shape_ == ShapeType::Plane) {
    planeNormal_ = (p.rotation * shapeNormal_).normalized();
    planeOffset_ = planeNormal_.dot(p.position);
  }
}

bool Collider::SetTransform(Real3 const& position, Quat const& rotation, Error& error) {
  if (!internal::CheckObstaclePose(*this, "SetTransform", position, rotation, error)) return false;
  Pose const saved[] = {start_, target_, now_, stageStart_, stageTarget_};
  Pose const pose{position, rotation.normalized()};
  start_ = target_ = stageStart_ = stageTarget_ = pose;
  Place(pose);
  if (internal::CheckWorldInRange(*this, "SetTransform: collider " + std::to_string(id_) + "'s", error) &&
      system_->CheckSeparated(system_->IndexOf(*this), "SetTransform", error))
    return true;
  start_ = saved[0];
  target_ = saved[1];
  stageStart_ = saved[3];
  stageTarget_ = saved[4];
  Place(saved[2]);
  system_->PrepareVertices();
  return false;
}

bool Collider::SetTargetTransform(Real3 const& position, Quat const& rotation, Error& error) {
  if (!internal::CheckObstaclePose(*this, "SetTargetTransform", position, rotation, error)) return false;
  target_ = {position, rotation.normalized()};
  return true;
}

namespace internal {

int ContactSystem::IndexOf(Collider const& collider) const {
  for (std::size_t c = 0; c < colliders_.size(); ++c)
    if (colliders_[c].get() == &collider) return static_cast<int>(c);
  return -1;
}

void ContactSystem::RestoreState() {
  anchors_ = savedAnchors_;
  for (auto& c : colliders_) {
    if (c->Moves()) continue;
    c->stageStart_ = c->stageTarget_ = c->start_;
    c->Place(c->start_);
  }
  progress_ = 1;
}

void ContactSystem::CommitStep() {
  for (auto& c : colliders_) {
    if (c->Moves()) continue;
    c->Place(c->target_);
    c->start_ = c->stageStart_ = c->stageTarget_ = c->target_;
  }
  stepFrom_ = 0;
  stepTo_ = 1;
}

Real3 ContactSystem::KinematicDisplacement(Collider const& c, Real3 const& y0) {
  // y0 carried rigidly from the stage-start pose to the pose now
  Collider::Pose const& a = c.stageStart_;
  Collider::Pose const& b = c.now_;
  return b.position + b.rotation * (a.rotation.conjugate() * (y0 - a.position)) - y0;
}

void ContactSystem::KinematicDisplacements() const {
  // a moving obstacle's vertices along their chords over the rest of its
  // way this stage (per unit of Newton's α), a plane's shift along its
  // normal; none once it is there
  planeShift_.assign(colliders_.size(), 0);
  if (progress_ >= 1) return;
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    Collider const& col = *colliders_[c];
    if (col.Moves() || !Sweeps(col)) continue;
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i)
      displacement_[i] = col.PlaceVertex(i - firstVertex_[c], col.stageTarget_) - x_[i];
    if (col.shape_ == ShapeType::Plane)
      planeShift_[c] = col.planeNormal_.dot(col.stageTarget_.position - col.now_.position);
  }
}

bool ContactSystem::AdvanceTarget(real fraction) {
  if (progress_ >= 1) return true;
  real const to = fraction >= 1 ? real(1) : progress_ + fraction * (1 - progress_);
  auto poseAt = [&](Collider const& c, real f) {
    return f >= 1 ? c.stageTarget_ : Collider::Interpolate(c.stageStart_, c.stageTarget_, f);
  };
  for (auto& c : colliders_)
    if (!c->Moves() && Sweeps(*c)) c->Place(poseAt(*c, to));
  // the bodies where the step left them, the obstacles at their new poses
  // (on their arcs, not the chords the safe step checked): every candidate apart
  UpdatePositions(x_);
  bool const apart = std::all_of(pairs_.begin(), pairs_.end(), [&](Pair const& pair) {
    Collider const& o = *colliders_[pair.obstacle];
    return o.Moves() || !Sweeps(o) || Gap(pair, x_) > 0;
  });
  if (!apart) {
    for (auto& c : colliders_)
      if (!c->Moves() && Sweeps(*c)) c->Place(poseAt(*c, progress_));
    UpdatePositions(x_);
    return false;
  }
  progress_ = to;
  return true;
}

// ---- positions ----

}  // namespace internal

void Collider::GetWorldVertices(DynamicArray<Real3>& vertices) const {
  vertices.resize(local_.size());
  for (std::size_t i = 0; i < local_.size(); ++i) {
    Vertex const& v = local_[i];
    vertices[i] = rigid_         ? rigid_->TransformPoint(v.local)
                  : articulated_ ? Real3(articulated_->GetLinkPosition(path_.link) +
                                         articulated_->GetLinkRotation(path_.link) * v.local)
                  : nodal_       ? nodal_->GetNodePosition(v.node)
                                 : PlaceVertex(static_cast<int>(i), now_);
  }
}

namespace internal {

void ContactSystem::UpdatePositions(DynamicArray<Real3>& x) const {
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    Collider const& col = *colliders_[c];
    int const first = firstVertex_[c];
    if (col.articulated_) col.articulated_->ComputeLinkFrame(col.path_);
    if (col.IsRigid()) {
      Real33 const r = col.FrameRotation().toRotationMatrix();
      Real3 const t = col.FramePosition();
      for (std::size_t i = 0; i < col.local_.size(); ++i) x[first + i] = t + r * col.local_[i].local;
    } else if (col.nodal_) {
      for (std::size_t i = 0; i < col.local_.size(); ++i) x[first + i] = col.nodal_->GetNodePosition(col.local_[i].node);
    } else {
      for (std::size_t i = 0; i < col.local_.size(); ++i) x[first + i] = col.PlaceVertex(static_cast<int>(i), col.now_);
    }
  }
}

// ---- candidates ----

void ContactSystem::BeginStage(StageContext const& stage) {
  ScopedSeconds timer(times_.broadPhase);
  executor_ = stage.executor;
  // the kinematic obstacles' share of their step's motion: from where they
  // are to the pose at the stage's end (reached by AdvanceTarget)
  progress_ = 1;
  for (auto& c : colliders_) {
    if (c->Moves()) continue;
    auto at = [&](real f) {
      return c->start_ == c->target_ || f <= 0 ? c->start_
             : f >= 1                          ? c->target_
                                               : Collider::Interpolate(c->start_, c->target_, f);
    };
    c->stageStart_ = at(stepFrom_);
    c->stageTarget_ = at(stepTo_);
    c->Place(c->stageStart_);
    if (Sweeps(*c)) progress_ = 0;
  }
  PrepareVertices();
  // each vertex's displacement bound for the stage: twice the free motion
  // (velocity and gravity over the stage) of the body's fastest vertex, plus
  // d̂. The body's fastest, not the vertex's own: a vertex at rest is pushed
  // by the rest of its body (a ball's bottom spreads as its top lands on it)
  real const h = stage.coefficients.duration;
  real const pushed = KinematicTravel();  // a moving obstacle can push a body this far
  bound_.assign(x_.size(), 0);
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    Collider const& col = *colliders_[c];
    if (!col.Moves()) continue;
    real speed = 0;
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) {
      if (col.rigid_) {
        Real3 const arm = x_[i] - col.rigid_->GetPosition();
        speed = std::max(speed, (col.rigid_->GetLinearVelocity() + col.rigid_->GetAngularVelocity().cross(arm)).norm());
      } else if (col.articulated_) {
        int const link = col.path_.link;
        Real3 const arm = x_[i] - col.articulated_->GetLinkCenterOfMass(link);
        speed = std::max(speed, (col.articulated_->GetLinkLinearVelocity(link) +
                                 col.articulated_->GetLinkAngularVelocity(link).cross(arm)).norm());
      } else {
        speed = std::max(speed, col.nodal_->GetNodeVelocity(col.local_[i - firstVertex_[c]].node).norm());
      }
    }
    real const bound =
        2 * (speed * h + stage.gravity.norm() * h * h + pushed) + params_.activationDistance;
    std::fill(bound_.begin() + firstVertex_[c], bound_.begin() + firstVertex_[c + 1], bound);
  }
  // self contact: only a body's deformation brings its primitives together,
  // so each vertex's bound there is on its displacement relative to the
  // body's mean displacement: its velocity relative to the mean velocity
  // over the stage, plus d̂ (a falling ball's surface does not reach across
  // the ball). Once, not twice like the obstacle bound: a stage that needs
  // more finds its candidates again (RecenterStepBounds), and a cloth's self
  // candidates grow with the bound's cube (a 12 × 12 cloth folding at dt =
  // 1/30: 3.5 times fewer, half the time, the same Newton iterations). Per
  // vertex, not the body's largest: a cloth draped on a sphere whose edges
  // still swing at 3 m/s keeps its resting middle's bounds small (24 × 24
  // nodes at dt = 1/60: docs/contact.md "Costs")
  vertexSelfBound_.assign(x_.size(), 0);
  for (int c = 0; c < static_cast<int>(colliders_.size()); ++c) {
    if (!MayTouch(c, c)) continue;
    NodalActor const& nodal = *colliders_[c]->nodal_;
    int const first = firstVertex_[c], count = firstVertex_[c + 1] - first;
    Real3 mean = Real3::Zero();
    for (int i = 0; i < count; ++i) mean += nodal.GetNodeVelocity(colliders_[c]->local_[i].node) / count;
    for (int i = 0; i < count; ++i) {
      Real3 const v = nodal.GetNodeVelocity(colliders_[c]->local_[i].node);
      // an impact stops part of a body within the stage: a vertex's motion
      // relative to the mean can then reach its own speed or the mean's (it
      // stops, or the rest of the body does). Half of that was 1.5 times
      // faster on the 16 × 16 and 24 × 24 cloths on the sphere, but Newton
      // failed on the 32 × 32 one landing at dt = 1/60
      real const speed = std::max({(v - mean).norm(), v.norm(), mean.norm()});
      vertexSelfBound_[first + i] = speed * h + params_.activationDistance;
    }
  }
  ++treeStamp_;
  FindPairs();
  ForPairs(static_cast<int>(pairs_.size()), [this](int begin, int end) {
    for (int p = begin; p < end; ++p) LagFriction(pairs_[p]);
  });
  pairValue_.resize(pairs_.size());
}

real ContactSystem::KinematicTravel() const {
  // how far a moving obstacle can push a body this stage: the longest path
  // of its vertices (a plane's: its shift, and its turn over the reach of
  // the bodies' vertices)
  real travel = 0, reach = 0;
  for (std::size_t c = 0; c < colliders_.size(); ++c)
    if (colliders_[c]->Moves())
      for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) reach = std::max(reach, x_[i].norm());
  for (auto const& c : colliders_) {
    if (c->Moves() || !Sweeps(*c)) continue;
    real const angle = c->stageStart_.rotation.angularDistance(c->stageTarget_.rotation);
    real const shift = (c->stageTarget_.position - c->stageStart_.position).norm();
    if (c->shape_ == ShapeType::Plane) {
      travel = std::max(travel, shift + angle * (reach + c->stageStart_.position.norm()));
      continue;
    }
    for (std::size_t i = 0; i < c->local_.size(); ++i)
      travel = std::max(travel, (c->PlaceVertex(static_cast<int>(i), c->stageTarget_) -
                                 c->PlaceVertex(static_cast<int>(i), c->stageStart_)).norm() +
                                    angle * angle / 8 * c->shapeVertices_[i].norm());
  }
  return travel;
}

ContactSystem::ObstacleTrees const& ContactSystem::TreesOf(int obstacleIndex) {
  if (trees_.size() != colliders_.size()) {
    trees_.clear();
    trees_.resize(colliders_.size());
  }
  std::unique_ptr<ObstacleTrees>& trees = trees_[obstacleIndex];
  Collider const& o = *colliders_[obstacleIndex];
  // a static obstacle's trees are built once per pose; a body's once per
  // stage, over its primitives' boxes inflated by its displacement bound; a
  // kinematic obstacle's once per stage over its sweep (the boxes at its
  // stage start and end, inflated by the arc's distance from the chord)
  bool const sweeps = !o.Moves() && Sweeps(o);
  if (!trees || ((o.Moves() || sweeps) && trees->stamp != treeStamp_) ||
      (!o.Moves() && trees->poseVersion != o.poseVersion_)) {
    if (!trees) trees = std::make_unique<ObstacleTrees>();
    trees->stamp = treeStamp_;
    trees->poseVersion = o.poseVersion_;
    int const f = firstVertex_[obstacleIndex];
    real margin = o.Moves() && !bound_.empty() ? bound_[f] : 0;
    DynamicArray<Real3>& end = sweepScratch_;
    end = x_;
    if (sweeps) {
      real radius = 0;
      for (int i = 0; i < static_cast<int>(o.local_.size()); ++i) {
        end[f + i] = o.PlaceVertex(i, o.stageTarget_);
        radius = std::max(radius, o.shapeVertices_[i].norm());
      }
      real const angle = o.stageStart_.rotation.angularDistance(o.stageTarget_.rotation);
      margin += radius * angle * angle / 8;  // r (1 − cos(θ/2)) <= r θ²/8
    }
    auto box = [&](std::initializer_list<int> v) {
      contact::Aabb b = BoxOf(x_, v, margin);
      if (sweeps) b = Merge(b, BoxOf(end, v, margin));
      return b;
    };
    DynamicArray<contact::Aabb>& boxes = treeBoxScratch_;
    Error ignored;  // the boxes are finite: the shape was validated
    boxes.clear();
    for (auto const& t : o.triangles_) boxes.push_back(box({f + t[0], f + t[1], f + t[2]}));
    trees->triangles.Build(boxes, ignored);
    boxes.clear();
    for (auto const& e : o.edges_) boxes.push_back(box({f + e[0], f + e[1]}));
    trees->edges.Build(boxes, ignored);
    boxes.clear();
    for (int i = 0; i < static_cast<int>(o.local_.size()); ++i) boxes.push_back(box({f + i}));
    trees->vertices.Build(boxes, ignored);
  }
  return *trees;
}

contact::Aabb ContactSystem::SelfBox(std::initializer_list<int> vertices, real margin) const {
  real bound = 0;
  for (int i : vertices) bound = std::max(bound, vertexSelfBound_[i]);
  return BoxOf(x_, vertices, margin + bound);
}

real ContactSystem::SelfReach(Pair const& pair) const {
  int const split = SideSplit(pair.kind);
  real first = 0, second = 0;
  for (int k = 0; k < pair.numVertices; ++k) {
    real& side = k < split ? first : second;
    side = std::max(side, vertexSelfBound_[pair.v[k]]);
  }
  return first + second;
}

ContactSystem::ObstacleTrees const& ContactSystem::SelfTrees(int index) {
  // a body's primitives for its self contact: boxes inflated by the self
  // bounds of their vertices
  Collider const& o = *colliders_[index];
  int const f = firstVertex_[index];
  DynamicArray<contact::Aabb>& boxes = treeBoxScratch_;
  Error ignored;  // the boxes are finite: the positions are
  boxes.clear();
  for (auto const& t : o.triangles_) boxes.push_back(SelfBox({f + t[0], f + t[1], f + t[2]}, 0));
  selfTrees_.triangles.Build(boxes, ignored);
  boxes.clear();
  for (auto const& e : o.edges_) boxes.push_back(SelfBox({f + e[0], f + e[1]}, 0));
  selfTrees_.edges.Build(boxes, ignored);
  boxes.clear();
  for (int i = 0; i < static_cast<int>(o.local_.size()); ++i) boxes.push_back(SelfBox({f + i}, 0));
  selfTrees_.vertices.Build(boxes, ignored);
  return selfTrees_;
}

void ContactSystem::FindPairs() {
  pairs_.clear();
  for (int a = 0; a < static_cast<int>(colliders_.size()); ++a)
    for (int b = 0; b < static_cast<int>(colliders_.size()); ++b)
      if (MayTouch(a, b)) AddPairs(a, b);
}

void ContactSystem::AddPairs(int bodyIndex, int obstacleIndex) {
  Collider const& body = *colliders_[bodyIndex];
  Collider const& obstacle = *colliders_[obstacleIndex];
  int const fb = firstVertex_[bodyIndex], fo = firstVertex_[obstacleIndex];
  real const dhat = params_.activationDistance;
  real const thickness = body.thickness_ + obstacle.thickness_;
  real const mu = std::sqrt(body.friction_ * obstacle.friction_);
  bool const self = bodyIndex == obstacleIndex;
  // a self pair's primitives move at most their vertices' self bounds
  // relative to the body's mean: one whose gap exceeds both sides' largest
  // plus d̂ cannot reach d̂ this stage (the boxes below are coarser: a flat
  // cloth's neighbours)
  auto add = [&](DynamicArray<Pair>& out, PairKind kind, std::array<int, 4> v, std::array<bool, 4> onBody, int count,
                 real weight) {
    if (!(weight > 0)) return;
    // self contact: never between primitives that share a vertex or that are
    // already within reach in the rest shape (a rod's neighbouring segments
    // are closer than its diameter)
    if (self && (SharesVertex(v, count) || RestGap(bodyIndex, kind, v) <= dhat)) return;
    Pair pair;
    pair.kind = kind;
    pair.body = bodyIndex;
    pair.obstacle = obstacleIndex;
    pair.v = v;
    pair.onBody = onBody;
    pair.numVertices = count;
    pair.thickness = thickness;
    pair.weight = weight;
    pair.mu = mu;
    pair.key = PairKey(static_cast<int>(kind), body.id_, obstacle.id_, v);
    if (self && Gap(pair, x_, nullptr) > SelfReach(pair) + dhat) return;
    if (kind == PairKind::EdgeEdge)
      pair.mollifierThreshold = contact::EdgeEdgeMollifierThreshold(x_[v[0]], x_[v[1]], x_[v[2]], x_[v[3]]);
    out.push_back(pair);
  };
  int const nb = static_cast<int>(body.local_.size());
  if (obstacle.shape_ == ShapeType::Plane) {
    // a moving plane: the nearer of its gaps at the stage start and end,
    // less what its turn can add between them
    bool const sweeps = Sweeps(obstacle);
    Real3 const endNormal = (obstacle.stageTarget_.rotation * obstacle.shapeNormal_).normalized();
    real const endOffset = endNormal.dot(obstacle.stageTarget_.position);
    real const angle = obstacle.stageStart_.rotation.angularDistance(obstacle.stageTarget_.rotation);
    AppendPairsInOrder(nb, [&](int i, DynamicArray<Pair>& out) {
      real gap = obstacle.planeNormal_.dot(x_[fb + i]) - obstacle.planeOffset_ - thickness;
      if (sweeps)
        gap = std::min(gap, endNormal.dot(x_[fb + i]) - endOffset - thickness) -
              angle * ((x_[fb + i] - obstacle.stageStart_.position).norm() +
                       (obstacle.stageTarget_.position - obstacle.stageStart_.position).norm());
      if (gap < dhat + bound_[fb + i])
        add(out, PairKind::PlaneVertex, {fb + i, -1, -1, -1}, {true, false, false, false}, 1, body.vertexArea_[i]);
    });
    return;
  }
  // the body's primitives over the stage: their start boxes inflated by the
  // displacement bound, d̂ and the thickness, against the obstacle's trees
  real const margin = dhat + thickness + (self ? 0 : bound_[fb]);
  ObstacleTrees const& trees = self ? SelfTrees(bodyIndex) : TreesOf(obstacleIndex);
  DynamicArray<contact::Aabb>& boxes = boxScratch_;
  DynamicArray<contact::IndexPair>& found = pairScratch_;
  // body vertices against obstacle triangles, and free body vertices against
  // free obstacle points (spheres) and segments (capsules)
  boxes.clear();
  for (int i = 0; i < nb; ++i) boxes.push_back(self ? SelfBox({fb + i}, margin) : BoxOf(x_, {fb + i}, margin));
  // (each query's pairs are found on the stage's threads, then filtered by
  // add there, in the order found)
  auto each = [&](contact::Bvh const& tree, auto&& make) {
    FindBoxPairs(tree, boxes, found);
    AppendPairsInOrder(static_cast<int>(found.size()),
                       [&](int k, DynamicArray<Pair>& out) { make(out, found[k].i, found[k].j); });
  };
  each(trees.triangles, [&](DynamicArray<Pair>& out, int t, int i) {
    auto const& tri = obstacle.triangles_[t];
    add(out, PairKind::PointTriangle, {fb + i, fo + tri[0], fo + tri[1], fo + tri[2]}, {true, false, false, false},
        4, body.vertexArea_[i]);
  });
  each(trees.edges, [&](DynamicArray<Pair>& out, int e, int i) {
    if (obstacle.freeEdge_[e] && body.freeVertex_[i])  // a vertex on an edge: edge–edge covers it
      add(out, PairKind::PointEdge, {fb + i, fo + obstacle.edges_[e][0], fo + obstacle.edges_[e][1], -1},
          {true, false, false, false}, 3, body.vertexArea_[i]);
  });
  each(trees.vertices, [&](DynamicArray<Pair>& out, int j, int i) {
    if (obstacle.freeVertex_[j] && body.freeVertex_[i])
      add(out, PairKind::PointPoint, {fb + i, fo + j, -1, -1}, {true, false, false, false}, 2,
          std::max(body.vertexArea_[i], obstacle.vertexArea_[j]));
  });
  if (self) {
    // the loops below would find the same pairs again, from the other side
    boxes.clear();
    for (auto const& e : body.edges_) boxes.push_back(SelfBox({fb + e[0], fb + e[1]}, margin));
    each(trees.edges, [&](DynamicArray<Pair>& out, int f, int e) {
      if (e < f)
        add(out, PairKind::EdgeEdge,
            {fb + body.edges_[e][0], fb + body.edges_[e][1], fb + body.edges_[f][0], fb + body.edges_[f][1]},
            {true, true, false, false}, 4, std::max(body.edgeArea_[e], body.edgeArea_[f]));
    });
    return;
  }
  // obstacle vertices against body triangles
  boxes.clear();
  for (auto const& t : body.triangles_) boxes.push_back(BoxOf(x_, {fb + t[0], fb + t[1], fb + t[2]}, margin));
  each(trees.vertices, [&](DynamicArray<Pair>& out, int j, int t) {
    auto const& tri = body.triangles_[t];
    add(out, PairKind::PointTriangle, {fo + j, fb + tri[0], fb + tri[1], fb + tri[2]}, {false, true, true, true}, 4,
        std::max(obstacle.vertexArea_[j], TriangleArea(x_[fb + tri[0]], x_[fb + tri[1]], x_[fb + tri[2]])));
  });
  // edges against edges, and free obstacle points against free body segments
  boxes.clear();
  for (auto const& e : body.edges_) boxes.push_back(BoxOf(x_, {fb + e[0], fb + e[1]}, margin));
  each(trees.edges, [&](DynamicArray<Pair>& out, int f, int e) {
    add(out, PairKind::EdgeEdge,
        {fb + body.edges_[e][0], fb + body.edges_[e][1], fo + obstacle.edges_[f][0], fo + obstacle.edges_[f][1]},
        {true, true, false, false}, 4, std::max(body.edgeArea_[e], obstacle.edgeArea_[f]));
  });
  each(trees.vertices, [&](DynamicArray<Pair>& out, int j, int e) {
    if (obstacle.freeVertex_[j] && body.freeEdge_[e])
      add(out, PairKind::PointEdge, {fo + j, fb + body.edges_[e][0], fb + body.edges_[e][1], -1},
          {false, true, true, false}, 3, body.edgeArea_[e]);
  });
}

void ContactSystem::FindBoxPairs(contact::Bvh const& tree, DynamicArray<contact::Aabb> const& boxes,
                                 DynamicArray<contact::IndexPair>& found) {
  if (executor_) {
    tree.FindPairsWith(boxes, found, *executor_, queryChunks_);
  } else {
    tree.FindPairsWith(boxes, found);
  }
}

// ---- one pair ----

bool ContactSystem::SharesVertex(std::array<int, 4> const& v, int count) {
  for (int a = 0; a < count; ++a)
    for (int b = a + 1; b < count; ++b)
      if (v[a] == v[b]) return true;
  return false;
}

real ContactSystem::RestGap(int colliderIndex, PairKind kind, std::array<int, 4> const& v) const {
  // the pair's gap in the actor's rest shape (reference positions)
  Collider const& c = *colliders_[colliderIndex];
  auto rest = [&](int k) -> Real3 const& {
    return c.nodal_->GetNodeReferencePosition(c.local_[v[k] - firstVertex_[colliderIndex]].node);
  };
  real d2 = 0;
  switch (kind) {
    case PairKind::PointTriangle: d2 = contact::PointTriangleDistance2(rest(0), rest(1), rest(2), rest(3)); break;
    case PairKind::EdgeEdge: d2 = contact::EdgeEdgeDistance2(rest(0), rest(1), rest(2), rest(3)); break;
    case PairKind::PointEdge: d2 = contact::PointEdgeDistance2(rest(0), rest(1), rest(2)); break;
    case PairKind::PointPoint: d2 = contact::PointPointDistance2(rest(0), rest(1)); break;
    case PairKind::PlaneVertex: break;
  }
  return std::sqrt(d2) - 2 * c.thickness_;
}

real ContactSystem::BoxGap(Pair const& pair) const {
  int const split = SideSplit(pair.kind);
  Real3 lower[2], upper[2];
  for (int k = 0; k < pair.numVertices; ++k) {
    int const side = k < split ? 0 : 1;
    Real3 const& p = x_[pair.v[k]];
    bool const first = k == 0 || k == split;
    lower[side] = first ? p : Real3(lower[side].cwiseMin(p));
    upper[side] = first ? p : Real3(upper[side].cwiseMax(p));
  }
  Real3 const apart = (lower[0] - upper[1]).cwiseMax(lower[1] - upper[0]).cwiseMax(0);
  return apart.norm() - pair.thickness;
}

real ContactSystem::Gap(Pair const& pair, DynamicArray<Real3> const& x, Vector12* gradient) const {
  std::array<Real3, 4> p;
  for (int k = 0; k < pair.numVertices; ++k) p[k] = x[pair.v[k]];
  return GapAt(pair, p, gradient);
}

real ContactSystem::GapAt(Pair const& pair, std::array<Real3, 4> const& x, Vector12* gradient) const {
  if (pair.kind == PairKind::PlaneVertex) {
    Collider const& plane = *colliders_[pair.obstacle];
    if (gradient) *gradient << plane.planeNormal_, Real3::Zero(), Real3::Zero(), Real3::Zero();
    return plane.planeNormal_.dot(x[0]) - plane.planeOffset_ - pair.thickness;
  }
  real d2 = 0;
  Vector12 g = Vector12::Zero();
  switch (pair.kind) {
    case PairKind::PointTriangle: {
      auto const type = contact::PointTriangleDistanceType(x[0], x[1], x[2], x[3]);
      d2 = contact::PointTriangleDistance2(x[0], x[1], x[2], x[3], type);
      if (gradient) g = contact::PointTriangleDistance2Gradient(x[0], x[1], x[2], x[3], type);
      break;
    }
    case PairKind::EdgeEdge: {
      auto const type = contact::EdgeEdgeDistanceType(x[0], x[1], x[2], x[3]);
      d2 = contact::EdgeEdgeDistance2(x[0], x[1], x[2], x[3], type);
      if (gradient) g = contact::EdgeEdgeDistance2Gradient(x[0], x[1], x[2], x[3], type);
      break;
    }
    case PairKind::PointEdge: {
      auto const type = contact::PointEdgeDistanceType(x[0], x[1], x[2]);
      d2 = contact::PointEdgeDistance2(x[0], x[1], x[2], type);
      if (gradient) g.head<9>() = contact::PointEdgeDistance2Gradient(x[0], x[1], x[2], type);
      break;
    }
    case PairKind::PointPoint:
      d2 = contact::PointPointDistance2(x[0], x[1]);
      if (gradient) g.head<6>() = contact::PointPointDistance2Gradient(x[0], x[1]);
      break;
    case PairKind::PlaneVertex: break;
  }
  real const d = std::sqrt(d2);
  if (gradient) *gradient = d > 0 ? Vector12(g / (2 * d)) : Vector12::Zero();  // ∇d = ∇d²/(2d)
  return d - pair.thickness;
}

Real3 ContactSystem::Slip(Pair const& pair, DynamicArray<Real3> const& x) const {
  // side A's contact point's displacement less side B's: a nodal side's
  // closest point through its vertices, a rigid side's contact point at the
  // stage's velocities, Δc + φ × a⁰ (a sphere rolls with v = ωr exactly
  // rather than slipping by its chord)
  Real3 slip = pair.slip0;
  for (int side = 0; side < 2; ++side) {
    Collider const& c = *colliders_[side == 0 ? pair.body : pair.obstacle];
    if (c.IsRigid()) {
      real const sign = side == 0 ? 1 : -1;
      slip += sign * (c.FramePosition() - pair.center0[side] + StageTurn(pair, side).cross(pair.arm0[side]));
    } else if (c.nodal_) {
      for (int k = 0; k < pair.numVertices; ++k)
        if (pair.onBody[k] == (side == 0)) slip += pair.gamma[k] * (x[pair.v[k]] - x0_[pair.v[k]]);
    } else if (Sweeps(c)) {
      // a kinematic obstacle (side B): its material point at the contact
      if (pair.kind == PairKind::PlaneVertex) {
        slip -= KinematicDisplacement(c, x0_[pair.v[0]]);
      } else {
        for (int k = 0; k < pair.numVertices; ++k)
          if (!pair.onBody[k]) slip += pair.gamma[k] * (x[pair.v[k]] - x0_[pair.v[k]]);
      }
    }
  }
  return slip;
}
void ContactSystem::LagFriction(Pair& pair) const {
  // the normal force at the stage start, the tangent plane there and the
  // weights γ of the closest points: ∂d/∂xₖ = γₖ n (n from side B towards
  // side A, the pair's `body`)
  pair.lambda = 0;
  Vector12 grad;
  real const d = Gap(pair, x0_, &grad);
  real const dhat = params_.activationDistance;
  if (!(d > 0) || d >= dhat || pair.mu == 0) return;
  Real3 sideGrad = Real3::Zero();
  for (int k = 0; k < pair.numVertices; ++k)
    if (pair.onBody[k]) sideGrad += grad.segment<3>(3 * k);
  if (sideGrad.norm() == 0) return;
  Real3 const n = sideGrad.normalized();
  pair.lambda = -params_.stiffness * pair.weight * contact::BarrierDerivative(d / dhat);
  pair.basis = contact::PointPointTangentBasis(n, Real3::Zero());
  for (int k = 0; k < pair.numVertices; ++k) pair.gamma[k] = grad.segment<3>(3 * k).dot(n);
  // each rigid side's material point at the contact: its closest point less
  // its thickness towards the other side (a sphere's contact point, not its
  // centre), as an arm from its centre
  for (int side = 0; side < 2; ++side) {
    Collider const& c = *colliders_[side == 0 ? pair.body : pair.obstacle];
    if (!c.IsRigid()) continue;
    real const sign = side == 0 ? 1 : -1;
    Real3 point = -sign * c.thickness_ * n;
    for (int k = 0; k < pair.numVertices; ++k)
      if (pair.onBody[k] == (side == 0)) point += sign * pair.gamma[k] * x0_[pair.v[k]];
    pair.center0[side] = c.FramePosition();
    pair.rotation0[side] = c.FrameRotation();
    pair.arm0[side] = point - pair.center0[side];
  }
  auto const it = std::lower_bound(anchors_.begin(), anchors_.end(), pair.key,
                                   [](auto const& anchor, std::uint64_t key) { return anchor.first < key; });
  bool const found = it != anchors_.end() && it->first == pair.key;
  pair.slip0 = found ? Real3(pair.basis * (pair.basis.transpose() * it->second)) : Real3::Zero();
}
namespace {
/// The barrier of a pair of n coordinates in the first n of 12 coordinates.
template <int n>
contact::ValueGradientHessian<12> Embedded(contact::ValueGradientHessian<n> const& e) {
  contact::ValueGradientHessian<12> r;
  r.value = e.value;
  r.gradient.head<n>() = e.gradient;
  r.hessian.topLeftCorner<n, n>() = e.hessian;
  return r;
}
}  // namespace

contact::ValueGradientHessian<12> ContactSystem::PairBarrier(Pair const& pair, bool derivatives,
                                                             bool projected) const {
  using contact::BarrierHessian;
  BarrierHessian const form = projected ? BarrierHessian::Projected : BarrierHessian::Exact;
  contact::ValueGradientHessian<12> e;
  real const dhat = params_.activationDistance;
  real const kw = params_.stiffness * pair.weight;
  auto const& x = x_;
  auto const& v = pair.v;
  // most candidates are beyond d̂: their boxes' gap says so without a
  // distance (a lower bound of it: the barrier is zero, as it would be)
  if (pair.kind != PairKind::PlaneVertex && BoxGap(pair) >= dhat) return e;
  real const d = Gap(pair, x_);
  if (!(d > 0)) {
    e.value = std::numeric_limits<real>::infinity();
    return e;
  }
  if (d < dhat && !derivatives) {
    e.value = kw * dhat * contact::Barrier(d / dhat);
    if (pair.kind == PairKind::EdgeEdge)
      e.value *= contact::EdgeEdgeMollifier(x[v[0]], x[v[1]], x[v[2]], x[v[3]], pair.mollifierThreshold);
  } else if (d < dhat) {
    contact::BarrierParams const barrier{pair.thickness, dhat, kw};
    switch (pair.kind) {
      case PairKind::PlaneVertex: {
        // the signed gap is linear in the vertex: a convex barrier of it
        Real3 const& normal = colliders_[pair.obstacle]->planeNormal_;
        e.value = kw * dhat * contact::Barrier(d / dhat);
        e.gradient.head<3>() = kw * contact::BarrierDerivative(d / dhat) * normal;
        e.hessian.topLeftCorner<3, 3>() =
            (kw * contact::BarrierSecondDerivative(d / dhat) / dhat) * normal * normal.transpose();
        break;
      }
      case PairKind::PointTriangle: {
        auto const type = contact::PointTriangleDistanceType(x[v[0]], x[v[1]], x[v[2]], x[v[3]]);
        e = contact::BarrierEnergy<12>(
            contact::PointTriangleDistance2Derivatives(x[v[0]], x[v[1]], x[v[2]], x[v[3]], type), barrier, form);
        break;
      }
      case PairKind::EdgeEdge: {
        // the barrier times IPC's mollifier of nearly parallel edges
        auto const type = contact::EdgeEdgeDistanceType(x[v[0]], x[v[1]], x[v[2]], x[v[3]]);
        auto const b = contact::BarrierEnergy<12>(
            contact::EdgeEdgeDistance2Derivatives(x[v[0]], x[v[1]], x[v[2]], x[v[3]], type), barrier,
            BarrierHessian::Exact);
        e = contact::Multiply(
            contact::EdgeEdgeMollifierDerivatives(x[v[0]], x[v[1]], x[v[2]], x[v[3]], pair.mollifierThreshold), b);
        if (projected) e.hessian = contact::ProjectToPsd<12>(e.hessian);
        break;
      }
      case PairKind::PointEdge: {
        auto const type = contact::PointEdgeDistanceType(x[v[0]], x[v[1]], x[v[2]]);
        e = Embedded<9>(contact::BarrierEnergy<9>(contact::PointEdgeDistance2Derivatives(x[v[0]], x[v[1]], x[v[2]], type),
                                                  barrier, form));
        break;
      }
      case PairKind::PointPoint: {
        contact::ValueGradientHessian<6> q;
        q.value = contact::PointPointDistance2(x[v[0]], x[v[1]]);
        q.gradient = contact::PointPointDistance2Gradient(x[v[0]], x[v[1]]);
        q.hessian = contact::PointPointDistance2Hessian(x[v[0]], x[v[1]]);
        e = Embedded<6>(contact::BarrierEnergy<6>(q, barrier, form));
        break;
      }
    }
  }
  return e;
}

Real3 ContactSystem::StageTurn(Pair const& pair, int side) const {
  Collider const& c = *colliders_[side == 0 ? pair.body : pair.obstacle];
  return Log(c.FrameRotation() * pair.rotation0[side].conjugate());
}
contact::TangentialFriction ContactSystem::PairFriction(Pair const& pair, DynamicArray<Real3> const& x) const {
  if (pair.lambda <= 0) return {};
  return contact::EvaluateTangentialFriction(pair.basis.transpose() * Slip(pair, x), pair.mu * pair.lambda,
                                             params_.frictionRampWidth);
}

// ---- the stage term ----

void ContactSystem::PairDofs(Pair const& pair, DynamicArray<int>& dofs) const {
  // two links of one mechanism: the union of their paths' DoFs, ascending
  if (LinksOfOneActor(*colliders_[pair.body], *colliders_[pair.obstacle])) {
    AppendPathUnion(*colliders_[pair.body], *colliders_[pair.obstacle], dofs);
    return;
  }
  // side A's DoFs, then side B's (none for a static obstacle): a rigid side's
  // 6, a link's path DoFs, a nodal side's 3 per vertex of the pair, in the
  // pair's vertex order
  for (int side = 0; side < 2; ++side) {
    int const index = side == 0 ? pair.body : pair.obstacle;
    Collider const& c = *colliders_[index];
    if (c.IsRigid()) {
      for (int k = 0; k < c.NumFrameDofs(); ++k) dofs.push_back(c.FrameDof(k));
    } else if (c.nodal_) {
      int const o = c.nodal_->GetDofOffset(), stride = c.nodal_->GetNodeDofStride();
      for (int k = 0; k < pair.numVertices; ++k) {
        if (pair.onBody[k] != (side == 0)) continue;
        int const node = c.local_[pair.v[k] - firstVertex_[index]].node;
        for (int j = 0; j < 3; ++j) dofs.push_back(o + stride * node + j);
      }
    }
  }
}
void ContactSystem::AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const {
  for (auto const& c : colliders_) {
    if (!c->articulated_ || c->path_.dofs.empty()) continue;
    dofLists.emplace_back();
    for (int k = 0; k < c->NumFrameDofs(); ++k) dofLists.back().push_back(c->FrameDof(k));
  }
  // two links of one mechanism that may touch: the union of their paths, the
  // block of their contacts (which couples two branches of the tree: the
  // actor is then solved as one dense block, as with a constraint between
  // two of its links)
  int const count = static_cast<int>(colliders_.size());
  for (int a = 0; a < count; ++a)
    for (int b = a + 1; b < count; ++b) {
      Collider const& ca = *colliders_[a];
      Collider const& cb = *colliders_[b];
      if (LinksOfOneActor(ca, cb) && MayTouch(a, b)) AppendPathUnion(ca, cb, dofLists.emplace_back());
    }
}

void ContactSystem::AppendStageContributorDofs(StageDofLists& dofLists) const {
  for (Pair const& pair : pairs_) PairDofs(pair, dofLists.Add());
}

void ContactSystem::AddEnergy(HessianAssembler const& assembler, int, EnergySum& sum) const {
  ScopedSeconds timer(times_.narrowPhase);
  // (the positions on every rank: the safe step and the recentering test
  // that follow read them)
  UpdatePositions(x_);
  // across ranks every rank holds every pair (the scene is replicated): the
  // first part counts their energy, once
  if (assembler.GetPart() != 0) return;
  // each pair's on the stage's threads, summed in pair order
  int const count = static_cast<int>(pairs_.size());
  ForPairs(count, [this](int begin, int end) {
    for (int p = begin; p < end; ++p) pairValue_[p] = PairBarrier(pairs_[p], false).value + PairFriction(pairs_[p], x_).energy;
  });
  for (int p = 0; p < count; ++p) sum.Add(pairValue_[p]);
}

void ContactSystem::AddGradientAndHessian(HessianAssembler& assembler, int, AssemblyOptions const& options) const {
  ScopedSeconds timer(times_.assembly);
  UpdatePositions(x_);
  // at most 2 kMaxLinkPathDofs: two links (a rigid side has 6 DoFs, a
  // nodal triangle 9)
  constexpr int kMaxDofs = 2 * kMaxLinkPathDofs;
  using DofVector = Eigen::Matrix<real, Eigen::Dynamic, 1, 0, kMaxDofs, 1>;
  using DofMatrix = Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDofs, kMaxDofs>;
  using VertexJacobian = Eigen::Matrix<real, 12, Eigen::Dynamic, 0, 12, kMaxDofs>;
  using SlipJacobian = Eigen::Matrix<real, 3, Eigen::Dynamic, 0, 3, kMaxDofs>;
  // each pair writes only its own staging slots (AddDynamicBlock): any
  // order, any thread
  assembler.ParallelFor(static_cast<int>(pairs_.size()), kPairGrain, [&](int begin, int end, int) {
  for (int p = begin; p < end; ++p) {
    Pair const& pair = pairs_[p];
    contact::ValueGradientHessian<12> const e = PairBarrier(pair, true, options.projectHessian);
    int const n = 3 * pair.numVertices;
    if (e.gradient.head(n).isZero(0) && pair.lambda <= 0) continue;
    contact::TangentialFriction const friction = PairFriction(pair, x_);
    // the vertices' positions and the slip as functions of the pair's DoFs
    // (PairDofs' order): J (vertices), Jf (slip), and each rigid side's
    // rotation curvature of the barrier and (a link) the barrier's wrench
    // on its frame
    int const m = PairColumnCount(pair);
    VertexJacobian J = VertexJacobian::Zero(12, m);
    SlipJacobian Jf = SlipJacobian::Zero(3, m);
    std::array<Real33, 2> curvature{Real33::Zero(), Real33::Zero()};
    std::array<Real3, 2> wrenchForce{Real3::Zero(), Real3::Zero()}, wrenchMoment{Real3::Zero(), Real3::Zero()};
    std::array<int, 2> frameColumn{-1, -1};
    int column = 0;
    for (int side = 0; side < 2; ++side) {
      Collider const& c = *colliders_[side == 0 ? pair.body : pair.obstacle];
      real const sign = side == 0 ? 1 : -1;
      if (c.IsRigid()) {
        // (δt, δθ) of the frame: a rigid actor's DoFs; a link's path DoFs
        // through the frame's Jacobian B
        int const dofs = c.NumFrameDofs();
        auto place = [&](auto& target, int row, Eigen::Matrix<real, 3, 6> const& rows) {
          if (c.rigid_) {
            target.template block<3, 6>(row, column) = rows;
          } else {
            target.block(row, column, 3, dofs).noalias() = rows * c.path_.jacobian;
          }
        };
        Real3 const center = c.FramePosition();
        Eigen::Matrix<real, 3, 6> rows;
        for (int k = 0; k < pair.numVertices; ++k) {
          if (pair.onBody[k] != (side == 0)) continue;
          Real3 const arm = x_[pair.v[k]] - center;
          Real3 const g = e.gradient.segment<3>(3 * k);
          rows << Real33::Identity(), -Hat(arm);
          place(J, 3 * k, rows);
          curvature[side] += RotatedVectorCurvature(g, arm);
          wrenchForce[side] += g;
          wrenchMoment[side] += arm.cross(g);
        }
        // ∂slip/∂(δt, δθ) = ±[I, −Hat(a⁰) J_l⁻¹(φ)] (the chart's curvature
        // dropped: the slip is nearly linear in φ over a stage)
        rows << sign * Real33::Identity(), -sign * Hat(pair.arm0[side]) * LeftJacobianInverse(StageTurn(pair, side));
        place(Jf, 0, rows);
        frameColumn[side] = column;
        column += dofs;
      } else if (c.nodal_) {
        // a node's world position is T(X + u): R_T on its 3 DoFs
        Real33 const r = c.nodal_->GetTransformRotation().toRotationMatrix();
        for (int k = 0; k < pair.numVertices; ++k) {
          if (pair.onBody[k] != (side == 0)) continue;
          J.block<3, 3>(3 * k, column) = r;
          Jf.block<3, 3>(0, column) = pair.gamma[k] * r;
          column += 3;
        }
      }
    }
    Real3 const force = pair.basis * friction.gradient;
    Real33 const stiffness = pair.basis * friction.hessian * pair.basis.transpose();
    // the barrier (projected: PSD) and the friction (PSD by construction)
    DofVector gq = J.topRows(n).transpose() * e.gradient.head(n) + Jf.transpose() * force;
    // an obstacle on its way to its stage target: the barrier's gradient
    // after the rest of that way, to first order (H Δo over its vertices; a
    // plane's shift s moves the gap by −s), so that the step carries the
    // body along
    if (Collider const& o = *colliders_[pair.obstacle]; !o.Moves() && progress_ < 1 && Sweeps(o)) {
      Vector12 moved = Vector12::Zero();
      if (pair.kind == PairKind::PlaneVertex) {
        moved.head<3>() = -o.planeNormal_.dot(o.stageTarget_.position - o.now_.position) * o.planeNormal_;
      } else {
        for (int k = 0; k < pair.numVertices; ++k)
          if (!pair.onBody[k])
            moved.segment<3>(3 * k) =
                o.PlaceVertex(pair.v[k] - firstVertex_[pair.obstacle], o.stageTarget_) - x_[pair.v[k]];
      }
      // (H's columns of the obstacle's vertices; a plane's shift as the body
      // vertex's opposite move)
      gq += J.topRows(n).transpose() * (e.hessian.topLeftCorner(n, n) * moved.head(n));
    }
    DofMatrix Hq = J.topRows(n).transpose() * e.hessian.topLeftCorner(n, n) * J.topRows(n) +
                   Jf.transpose() * stiffness * Jf;
    if (!options.projectHessian)
      for (int side = 0; side < 2; ++side) {
        int const f = frameColumn[side];
        if (f < 0) continue;
        Collider const& c = *colliders_[side == 0 ? pair.body : pair.obstacle];
        if (c.rigid_) {
          Hq.block<3, 3>(f + 3, f + 3) += curvature[side];
          continue;
        }
        // a link: Bθᵀ C Bθ and the frame's own curvature against the
        // barrier's wrench (F at the frame origin, M)
        LinkPath const& path = c.path_;
        int const dofs = c.NumFrameDofs();
        auto const turn = path.jacobian.bottomRows<3>();
        // (C Bθ first, into fixed-capacity storage: no temporary on the heap)
        Eigen::Matrix<real, 3, Eigen::Dynamic, 0, 3, kMaxLinkPathDofs> const turned = curvature[side] * turn;
        Hq.block(f, f, dofs, dofs).noalias() += turn.transpose() * turned;
        path.AddCurvature(wrenchForce[side], wrenchMoment[side], [f](int i) { return f + i; }, Hq);
      }
    int const contributor = options.firstStageContributor + p;
    std::array<int, kMaxDofs> place;
    if (Collider const& a = *colliders_[pair.body], &b = *colliders_[pair.obstacle]; LinksOfOneActor(a, b)) {
      int const shared = MergePaths(a, b, place);
      // two links of one mechanism: their paths' common joints summed
      DofVector gu = DofVector::Zero(shared);
      DofMatrix Hu = DofMatrix::Zero(shared, shared);
      for (int i = 0; i < m; ++i) {
        gu(place[i]) += gq(i);
        for (int j = 0; j < m; ++j) Hu(place[i], place[j]) += Hq(i, j);
      }
      assembler.AddDynamicGradient(contributor, gu);
      assembler.AddDynamicBlock(contributor, Hu);
      continue;
    }
    assembler.AddDynamicGradient(contributor, gq);
    assembler.AddDynamicBlock(contributor, Hq);
  }
  });
}

int ContactSystem::MergePaths(Collider const& a, Collider const& b, std::array<int, 2 * kMaxLinkPathDofs>& place) {
  // the union of two ascending lists, merged: each side's columns (a's path
  // DoFs, then b's) to their place in it
  DynamicArray<int> const& da = a.path_.dofs;
  DynamicArray<int> const& db = b.path_.dofs;
  int const na = static_cast<int>(da.size()), nb = static_cast<int>(db.size());
  int i = 0, j = 0, count = 0;
  while (i < na || j < nb) {
    bool const takeA = j == nb || (i < na && da[i] <= db[j]);
    bool const takeB = i == na || (j < nb && db[j] <= da[i]);
    if (takeA) place[i++] = count;
    if (takeB) place[na + j++] = count;
    ++count;
  }
  return count;
}

void ContactSystem::AppendPathUnion(Collider const& a, Collider const& b, DynamicArray<int>& dofs) {
  std::array<int, 2 * kMaxLinkPathDofs> place;
  int const begin = static_cast<int>(dofs.size());
  dofs.resize(begin + MergePaths(a, b, place));
  int column = 0;
  for (Collider const* c : {&a, &b})
    for (int k = 0; k < c->NumFrameDofs(); ++k) dofs[begin + place[column++]] = c->FrameDof(k);
}

int ContactSystem::PairColumnCount(Pair const& pair) const {
  int count = 0;
  for (int side = 0; side < 2; ++side) {
    Collider const& c = *colliders_[side == 0 ? pair.body : pair.obstacle];
    if (c.IsRigid()) {
      count += c.NumFrameDofs();
    } else if (c.nodal_) {
      for (int k = 0; k < pair.numVertices; ++k) count += 3 * (pair.onBody[k] == (side == 0));
    }
  }
  return count;
}

// ---- the safe step ----

real ContactSystem::RigidPairCcd(Pair const& pair, Span<real const> delta, real tMax) const {
  // conservative advancement along the true paths — a rigid side's vertices
  // on arcs x(α) = c + α δt + Exp(α δθ) a, a link's with its frame at q ⊕ α δq
  // (forward kinematics along its path), a nodal side's on lines — with L
  // the sum of each side's largest speed per unit α (|δt| + |δθ| max|a| for a
  // rigid side, ArticulatedActor::LinkSpeedBound for a link): advancing by
  // (gap − target)/L never passes the target gap
  struct SideMotion {
    RigidActor const* rigid = nullptr;
    Collider const* link = nullptr;
    real const* jointStep = nullptr;  ///< a link's actor's share of δ
    Real3 center, dt, dr;
  };
  std::array<SideMotion, 2> motion;
  real speed = 0;
  for (int side = 0; side < 2; ++side) {
    Collider const& c = *colliders_[side == 0 ? pair.body : pair.obstacle];
    real sideSpeed = 0;
    if (c.rigid_) {
      int const o = c.rigid_->GetDofOffset();
      SideMotion& s = motion[side];
      s.rigid = c.rigid_;
      s.center = c.rigid_->GetPosition();
      s.dt = Real3(delta[o], delta[o + 1], delta[o + 2]);
      s.dr = Real3(delta[o + 3], delta[o + 4], delta[o + 5]);
      real armBound = 0;
      for (int k = 0; k < pair.numVertices; ++k)
        if (pair.onBody[k] == (side == 0)) armBound = std::max(armBound, (x_[pair.v[k]] - s.center).norm());
      sideSpeed = s.dt.norm() + s.dr.norm() * armBound;
    } else if (c.articulated_) {
      SideMotion& s = motion[side];
      s.link = &c;
      s.jointStep = delta.data() + c.articulated_->GetDofOffset();
      real armBound = 0;
      for (int k = 0; k < pair.numVertices; ++k)
        if (pair.onBody[k] == (side == 0)) armBound = std::max(armBound, (x_[pair.v[k]] - c.path_.position).norm());
      sideSpeed = c.articulated_->LinkSpeedBound(c.path_, s.jointStep, tMax, armBound);
    } else {
      for (int k = 0; k < pair.numVertices; ++k)
        if (pair.onBody[k] == (side == 0)) sideSpeed = std::max(sideSpeed, displacement_[pair.v[k]].norm());
    }
    speed += sideSpeed;
  }
  real const gap0 = Gap(pair, x_);
  if (!(gap0 > 0)) return 0;
  speed += std::abs(planeShift_[pair.obstacle]);
  if (speed == 0) return tMax;
  real const target = (1 - contact::kCcdRescale) * gap0;
  real const stop = contact::kCcdStopFraction * contact::kCcdRescale * gap0;
  real t = 0;
  std::array<Real3, 4> trial;  // the pair's vertices at t (its own: pairs run concurrently)
  for (int iteration = 0; iteration < params_.ccdMaxIterations; ++iteration) {
    for (int side = 0; side < 2; ++side) {
      SideMotion const& s = motion[side];
      if (s.link) {
        Real3 origin;
        Quat rotation;
        s.link->articulated_->ComputeLinkFrameAlong(s.link->path_, s.jointStep, t, origin, rotation);
        int const first = firstVertex_[side == 0 ? pair.body : pair.obstacle];
        for (int k = 0; k < pair.numVertices; ++k)
          if (pair.onBody[k] == (side == 0))
            trial[k] = origin + rotation * s.link->local_[pair.v[k] - first].local;
        continue;
      }
      Real33 const turn = s.rigid ? ExpMatrix(t * s.dr) : Real33::Identity();
      for (int k = 0; k < pair.numVertices; ++k) {
        if (pair.onBody[k] != (side == 0)) continue;
        Real3 const& x = x_[pair.v[k]];
        trial[k] = s.rigid ? Real3(s.center + t * s.dt + turn * (x - s.center)) : Real3(x + t * displacement_[pair.v[k]]);
      }
    }
    real const gap = GapAt(pair, trial) - t * planeShift_[pair.obstacle];  // a moving plane's shift
    if (gap - target <= stop) return t;
    t += (gap - target) / speed;
    if (t >= tMax) return tMax;
  }
  return t;
}
real ContactSystem::LinearPairCcd(Pair const& pair, DynamicArray<Real3> const& x, real scale) const {
  auto const& v = pair.v;
  auto dx = [&](int k) -> Real3 { return displacement_[v[k]] * scale; };
  real const thickness = pair.thickness;
  int const cap = params_.ccdMaxIterations;
  switch (pair.kind) {
    case PairKind::PlaneVertex: {
      Collider const& plane = *colliders_[pair.obstacle];
      return contact::PointPlaneCcd(x[v[0]], dx(0), thickness, plane.planeNormal_, plane.planeOffset_, scale * planeShift_[pair.obstacle], 1);
    }
    case PairKind::PointTriangle:
      return contact::PointTriangleCcd(x[v[0]], x[v[1]], x[v[2]], x[v[3]], dx(0), dx(1), dx(2), dx(3), thickness, 1, contact::kCcdRescale, cap);
    case PairKind::EdgeEdge:
      return contact::EdgeEdgeCcd(x[v[0]], x[v[1]], x[v[2]], x[v[3]], dx(0), dx(1), dx(2), dx(3), thickness, 1, contact::kCcdRescale, cap);
    case PairKind::PointEdge:
      return contact::PointEdgeCcd(x[v[0]], x[v[1]], x[v[2]], dx(0), dx(1), dx(2), thickness, 1, contact::kCcdRescale, cap);
    case PairKind::PointPoint: return contact::PointPointCcd(x[v[0]], x[v[1]], dx(0), dx(1), thickness, 1, contact::kCcdRescale, cap);
  }
  return 0;
}

real ContactSystem::SelfSafeStep(int c, real alpha) const {
  int const first = firstVertex_[c], count = firstVertex_[c + 1] - first;
  Real3 moved = Real3::Zero(), step = Real3::Zero();
  for (int i = first; i < first + count; ++i) {
    moved += (x_[i] - boundCenter_[i]) / count;
    step += displacement_[i] / count;
  }
  for (int i = first; i < first + count; ++i) {
    real const rate = (displacement_[i] - step).norm();
    if (rate == 0) continue;
    real const room = vertexSelfBound_[i] - (x_[i] - boundCenter_[i] - moved).norm();
    alpha = std::min(alpha, std::max(room, real(0)) / rate);
  }
  return alpha;
}

int ContactSystem::NodeDof(int c, int i) const {
  Collider const& col = *colliders_[c];
  return col.nodal_->GetDofOffset() + col.nodal_->GetNodeDofStride() * col.local_[i - firstVertex_[c]].node;
}

real ContactSystem::BoundRoom(int i) const {
  return std::max(bound_[i] - (x_[i] - boundCenter_[i]).norm(), real(0));
}

void ContactSystem::StepDisplacements(Span<real const> delta) const {
  UpdatePositions(x_);
  // each vertex's displacement along δ: exact for nodes (linear in α); a
  // rigid body's vertices move on arcs, bounded by the chord's rate for the
  // displacement bound and checked on the arcs by RigidPairCcd
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    Collider const& col = *colliders_[c];
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) displacement_[i].setZero();
    if (col.IsRigid()) {
      // the frame's (δt, δθ): a rigid actor's DoFs, a link's B δq
      Eigen::Matrix<real, 6, 1> frame;
      if (col.rigid_) {
        frame = Eigen::Map<Eigen::Matrix<real, 6, 1> const>(delta.data() + col.rigid_->GetDofOffset());
      } else {
        frame.setZero();
        for (int k = 0; k < col.NumFrameDofs(); ++k) frame += col.path_.jacobian.col(k) * delta[col.FrameDof(k)];
      }
      Real3 const dt = frame.head<3>(), dr = frame.tail<3>();
      Real3 const center = col.FramePosition();
      for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) displacement_[i] = dt + dr.cross(x_[i] - center);
    } else if (col.nodal_) {
      Real33 const r = col.nodal_->GetTransformRotation().toRotationMatrix();
      for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) {
        int const dof = NodeDof(static_cast<int>(c), i);
        displacement_[i] = r * Real3(delta[dof], delta[dof + 1], delta[dof + 2]);
      }
    }
  }
  KinematicDisplacements();
}

real ContactSystem::LargestSafeStep(Span<real const> delta, real alpha) const {
  ScopedSeconds timer(times_.ccd);
  StepDisplacements(delta);
  real safe = alpha;
  // the stage's displacement bound of every body's vertex
  for (std::size_t c = 0; c < colliders_.size(); ++c)
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1] && colliders_[c]->Moves(); ++i) {
      real const step = displacement_[i].norm();
      if (step > 0) safe = std::min(safe, BoundRoom(i) / step);
    }
  // the self-contact bound: each vertex's displacement relative to its
  // body's mean displacement
  for (int c = 0; c < static_cast<int>(colliders_.size()); ++c)
    if (HasSelfBound(c)) safe = std::min(safe, SelfSafeStep(c, safe));
  // continuous collision detection of every candidate along the step, each
  // up to the same α (its own result; the smallest wins whatever the order)
  int const count = static_cast<int>(pairs_.size());
  ForPairs(count, [&](int begin, int end) {
    for (int p = begin; p < end; ++p) {
      Pair const& pair = pairs_[p];
      pairValue_[p] = colliders_[pair.body]->IsRigid() || colliders_[pair.obstacle]->IsRigid()
                          ? RigidPairCcd(pair, delta, safe)
                          : safe * LinearPairCcd(pair, x_, safe);
    }
  });
  real result = safe;
  for (int p = 0; p < count; ++p) result = std::min(result, pairValue_[p]);
  return result;
}

void ContactSystem::LimitStepPerDof(Span<real> delta) const {
  ScopedSeconds timer(times_.ccd);
  // each vertex's own fraction: the room its bound leaves, then the time of
  // impact of each of its linear pairs along δ
  StepDisplacements(delta);
  vertexFraction_.assign(x_.size(), 1);
  for (std::size_t c = 0; c < colliders_.size(); ++c)
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1] && colliders_[c]->nodal_; ++i) {
      real const step = displacement_[i].norm();
      if (step > 0) vertexFraction_[i] = std::min(real(1), BoundRoom(i) / step);
    }
  int const count = static_cast<int>(pairs_.size());
  ForPairs(count, [this](int begin, int end) {
    for (int p = begin; p < end; ++p) {
      Pair const& pair = pairs_[p];
      bool const rigid = colliders_[pair.body]->IsRigid() || colliders_[pair.obstacle]->IsRigid();
      pairValue_[p] = rigid ? 1 : LinearPairCcd(pair, x_, 1);
    }
  });
  for (int p = 0; p < count; ++p) {
    real const fraction = pairValue_[p];
    if (fraction >= 1) continue;
    Pair const& pair = pairs_[p];
    for (int k = 0; k < pair.numVertices; ++k) vertexFraction_[pair.v[k]] = std::min(vertexFraction_[pair.v[k]], fraction);
  }
  // the nodal vertices' shares of δ scaled by them
  for (std::size_t c = 0; c < colliders_.size(); ++c)
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1] && colliders_[c]->nodal_; ++i) {
      int const dof = NodeDof(static_cast<int>(c), i);
      for (int k = 0; k < 3; ++k) delta[dof + k] *= vertexFraction_[i];
    }
}

bool ContactSystem::RecenterStepBounds() {
  ScopedSeconds timer(times_.broadPhase);
  UpdatePositions(x_);
  constexpr real kUsed = 0.9;  // of a bound, before the region is found again
  bool nearEdge = false;
  for (std::size_t c = 0; c < colliders_.size() && !nearEdge; ++c) {
    if (!colliders_[c]->Moves()) continue;
    int const first = firstVertex_[c], count = firstVertex_[c + 1] - first;
    Real3 moved = Real3::Zero();
    for (int i = first; i < first + count; ++i) {
      nearEdge = nearEdge || (x_[i] - boundCenter_[i]).norm() > kUsed * bound_[i];
      moved += (x_[i] - boundCenter_[i]) / count;
    }
    if (HasSelfBound(c))
      for (int i = first; i < first + count; ++i)
        nearEdge = nearEdge || (x_[i] - boundCenter_[i] - moved).norm() > kUsed * vertexSelfBound_[i];
  }
  if (!nearEdge) return false;
  boundCenter_ = x_;
  // the pairs again, each one found before keeping its stage-start data
  keptPairs_.swap(pairs_);
  keptKeys_.clear();
  for (int p = 0; p < static_cast<int>(keptPairs_.size()); ++p) keptKeys_.emplace_back(keptPairs_[p].key, p);
  std::sort(keptKeys_.begin(), keptKeys_.end());
  ++treeStamp_;
  FindPairs();
  keptFound_.assign(keptPairs_.size(), 0);
  pairValue_.resize(pairs_.size());
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    Pair& pair = pairs_[p];
    auto const it = std::lower_bound(keptKeys_.begin(), keptKeys_.end(), std::make_pair(pair.key, -1));
    bool const kept = it != keptKeys_.end() && it->first == pair.key;
    if (kept) {
      pair = keptPairs_[it->second];
      keptFound_[it->second] = 1;
    }
    pairValue_[p] = kept;
  }
  // a new pair is beyond d̂ at the stage start: no normal force
  ForPairs(static_cast<int>(pairs_.size()), [this](int begin, int end) {
    for (int p = begin; p < end; ++p)
      if (pairValue_[p] == 0) LagFriction(pairs_[p]);
  });
  // a pair out of reach now keeps its friction (its barrier is zero)
  for (std::size_t p = 0; p < keptPairs_.size(); ++p)
    if (!keptFound_[p] && keptPairs_[p].lambda > 0) pairs_.push_back(keptPairs_[p]);
  pairValue_.resize(pairs_.size());
  return true;
}

bool ContactSystem::AcceptsFirstIterate() const {
  ScopedSeconds timer(times_.ccd);
  // the move from the stage start to the first iterate, as a linear step
  // (the obstacles where they were at the stage start)
  UpdatePositions(x_);
  planeShift_.assign(colliders_.size(), 0);
  for (std::size_t i = 0; i < x_.size(); ++i) {
    displacement_[i] = x_[i] - x0_[i];
    if (displacement_[i].norm() > bound_[i]) return false;
  }
  // and each self-contact body's vertices within its self bound of its mean
  for (int c = 0; c < static_cast<int>(colliders_.size()); ++c) {
    if (!HasSelfBound(c)) continue;
    int const first = firstVertex_[c], count = firstVertex_[c + 1] - first;
    Real3 mean = Real3::Zero();
    for (int i = first; i < first + count; ++i) mean += displacement_[i] / count;
    for (int i = first; i < first + count; ++i)
      if ((displacement_[i] - mean).norm() > vertexSelfBound_[i]) return false;
  }
  int const count = static_cast<int>(pairs_.size());
  ForPairs(count, [this](int begin, int end) {
    for (int p = begin; p < end; ++p) pairValue_[p] = LinearPairCcd(pairs_[p], x0_, 1);
  });
  return std::all_of(pairValue_.begin(), pairValue_.begin() + count, [](real fraction) { return fraction >= 1; });
}

// ---- the stage end ----

void ContactSystem::EndStage() {
  UpdatePositions(x_);
  anchors_.clear();
  active_ = 0;
  minDistance_ = std::numeric_limits<real>::infinity();
  real const g = params_.frictionRampWidth;
  for (Pair const& pair : pairs_) {
    real const d = Gap(pair, x_);
    minDistance_ = std::min(minDistance_, d);
    if (d < params_.activationDistance) ++active_;
    if (pair.lambda <= 0) continue;
    // the slip from the anchor on the tangent plane; a sliding contact drags
    // its anchor to ḡ behind it
    Real3 slip = pair.basis * (pair.basis.transpose() * Slip(pair, x_));
    real const norm = slip.norm();
    if (norm > g) slip *= g / norm;
    anchors_.emplace_back(pair.key, slip);
  }
  // by key for LagFriction's search (in place: no allocation); equal keys,
  // were two pairs' hashes to collide, in a fixed order
  std::sort(anchors_.begin(), anchors_.end(), [](auto const& a, auto const& b) {
    return a.first != b.first ? a.first < b.first
                              : std::lexicographical_compare(a.second.data(), a.second.data() + 3, b.second.data(),
                                                             b.second.data() + 3);
  });
}

void ContactSystem::GetContacts(DynamicArray<ContactInfo>& contacts) const {
  contacts.clear();
  DynamicArray<Real3> x(x_.size());
  UpdatePositions(x);
  real const dhat = params_.activationDistance;
  for (Pair const& pair : pairs_) {
    Vector12 grad;
    real const d = Gap(pair, x, &grad);
    if (!(d < dhat) || !(d > 0)) continue;
    ContactInfo info;
    info.colliderA = colliders_[pair.body]->id_;
    info.colliderB = colliders_[pair.obstacle]->id_;
    Real3 bodyGrad = Real3::Zero(), point = Real3::Zero();
    real obstacleWeight = 0;
    for (int k = 0; k < pair.numVertices; ++k) {
      if (pair.onBody[k]) {
        bodyGrad += grad.segment<3>(3 * k);
      } else {
        real const w = grad.segment<3>(3 * k).norm();
        point += w * x[pair.v[k]];
        obstacleWeight += w;
      }
    }
    info.normal = bodyGrad.normalized();
    info.point = obstacleWeight > 0 ? Real3(point / obstacleWeight)
                                    : Real3(x[pair.v[0]] - (d + pair.thickness) * info.normal);
    info.distance = d;
    info.normalForce = -params_.stiffness * pair.weight * contact::BarrierDerivative(d / dhat);
    info.frictionForce = -(pair.basis * PairFriction(pair, x).gradient);
    contacts.push_back(info);
  }
}

}  // namespace internal
}  // namespace superdex
