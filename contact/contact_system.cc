#include <superdex/contact/contact_system.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include <superdex/actors/deformable_actor.h>
#include <superdex/actors/rod_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/contact/barrier.h>
#include <superdex/contact/ccd.h>
#include <superdex/contact/distance.h>
#include <superdex/core/so3.h>
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
         CheckPositive(params.frictionRampWidth, "contact.frictionRampWidth", error);
}

namespace {

using Vector12 = Eigen::Matrix<real, 12, 1>;
using Matrix12 = Eigen::Matrix<real, 12, 12>;
using Matrix32 = Eigen::Matrix<real, 3, 2>;

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

/// A unit vector orthogonal to n and a second completing the basis.
Matrix32 TangentBasis(Real3 const& n) {
  Real3 const helper = std::abs(n.x()) < 0.9 ? Real3::UnitX() : Real3::UnitY();
  Real3 const t1 = n.cross(helper).normalized();
  Matrix32 basis;
  basis.col(0) = t1;
  basis.col(1) = n.cross(t1);
  return basis;
}

}  // namespace

// ---- colliders ----

Collider* ContactSystem::Add(ColliderParams const& p, RigidActor* rigid, NodalActor* nodal, Error& error) {
  if (!CheckFinite(p.position, "position", error) || !CheckUnitQuat(p.rotation, "rotation", error) ||
      !CheckNonNegative(p.friction, "friction", error) || !CheckNonNegative(p.thickness, "thickness", error))
    return nullptr;
  if (p.link != -1) {
    error.Set(ErrorCode::NotSupported, "link: colliders on articulated links are not supported yet, got link " +
                                           std::to_string(p.link));
    return nullptr;
  }
  bool const onBody = rigid || nodal;
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
  if (p.shape == ShapeType::Plane && onBody) {
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
  if (rigid) c->actor_ = rigid->GetHandle();
  if (nodal) c->actor_ = nodal->GetHandle();
  Real33 const rotation = p.rotation.toRotationMatrix();
  auto place = [&](Real3 const& local) {
    Collider::Vertex v;
    v.local = p.position + rotation * local;  // the body frame, or world for an obstacle
    return v;
  };
  DynamicArray<std::array<int, 3>> triangles;
  switch (p.shape) {
    case ShapeType::Plane: {
      if (!CheckFinite(p.normal, "normal", error)) return nullptr;
      if (!(p.normal.norm() > 1e-12)) {
        error.Set(ErrorCode::InvalidArgument, "normal: must be non-zero, got " + Format(p.normal));
        return nullptr;
      }
      c->planeNormal_ = (rotation * p.normal).normalized();
      c->planeOffset_ = c->planeNormal_.dot(p.position);
      break;
    }
    case ShapeType::Sphere:
      if (!CheckPositive(p.radius, "radius", error)) return nullptr;
      c->thickness_ = p.radius;
      c->local_.push_back(place(Real3::Zero()));
      break;
    case ShapeType::Capsule:
      if (!CheckPositive(p.radius, "radius", error) || !CheckPositive(p.halfLength, "halfLength", error))
        return nullptr;
      c->thickness_ = p.radius;
      c->local_.push_back(place(Real3(0, 0, -p.halfLength)));
      c->local_.push_back(place(Real3(0, 0, p.halfLength)));
      c->edges_.push_back({0, 1});
      break;
    case ShapeType::Box: {
      if (!CheckPositive(p.halfExtents, "halfExtents", error)) return nullptr;
      for (int i = 0; i < 8; ++i)
        c->local_.push_back(place(Real3((i & 1) ? p.halfExtents.x() : -p.halfExtents.x(),
                                        (i & 2) ? p.halfExtents.y() : -p.halfExtents.y(),
                                        (i & 4) ? p.halfExtents.z() : -p.halfExtents.z())));
      // two outward triangles per face
      triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
      break;
    }
    case ShapeType::TriangleMesh: {
      if (p.vertices.empty() || p.triangles.empty()) {
        error.Set(ErrorCode::InvalidArgument, "vertices, triangles: a TriangleMesh needs both, got " +
                                                  std::to_string(p.vertices.size()) + " vertices and " +
                                                  std::to_string(p.triangles.size()) + " triangles");
        return nullptr;
      }
      for (std::size_t i = 0; i < p.vertices.size(); ++i) {
        if (!CheckFinite(p.vertices[i], "vertices[" + std::to_string(i) + "]", error)) return nullptr;
        c->local_.push_back(place(p.vertices[i]));
      }
      triangles = p.triangles;
      break;
    }
    case ShapeType::Surface: {
      DynamicArray<Real3> nodes;
      for (int i = 0; i < nodal->GetNumNodes(); ++i) nodes.push_back(nodal->GetNodePosition(i));
      if (nodal->GetType() == ActorType::Rod) {
        auto const* rod = static_cast<RodActor const*>(nodal);
        c->thickness_ = p.radius > 0 ? p.radius : rod->GetRadius();
        for (int e = 0; e + 1 < nodal->GetNumNodes(); ++e) c->edges_.push_back({e, e + 1});
      } else {
        auto const* body = static_cast<DeformableActor const*>(nodal);
        triangles = BoundaryOf(body->GetTetrahedra());
        for (auto const& t : body->GetTriangles()) triangles.push_back(t);
      }
      // every node is a vertex (interior nodes of a solid are never in a
      // primitive and never move into a candidate)
      for (int i = 0; i < nodal->GetNumNodes(); ++i) {
        Collider::Vertex v;
        v.node = i;
        c->local_.push_back(v);
      }
      if (!CheckNonNegative(p.radius, "radius", error)) return nullptr;
      break;
    }
  }
  // triangles: indices and degeneracy
  int const n = static_cast<int>(c->local_.size());
  auto at = [&](int i) {
    return c->local_[i].node >= 0 ? nodal->GetNodePosition(c->local_[i].node) : c->local_[i].local;
  };
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    auto const& tri = triangles[t];
    for (int i : tri)
      if (i < 0 || i >= n) {
        error.Set(ErrorCode::InvalidArgument, "triangles[" + std::to_string(t) + "]: vertex index " +
                                                  std::to_string(i) + " out of range [0, " + std::to_string(n) +
                                                  ")");
        return nullptr;
      }
    real const area = 0.5 * (at(tri[1]) - at(tri[0])).cross(at(tri[2]) - at(tri[0])).norm();
    if (!(area > 0)) {
      error.Set(ErrorCode::InvalidArgument,
                "triangles[" + std::to_string(t) + "]: degenerate triangle (zero area)");
      return nullptr;
    }
  }
  c->triangles_ = triangles;
  if (!triangles.empty()) c->edges_ = EdgesOf(triangles);
  // areas: a third of each adjacent triangle per vertex and edge; a
  // segment's vertices and edge its length times its diameter; a point the
  // disc of its radius
  c->vertexArea_.assign(n, 0);
  c->edgeArea_.assign(c->edges_.size(), 0);
  c->freeVertex_.assign(n, 1);
  c->freeEdge_.assign(c->edges_.size(), 1);
  for (auto const& tri : c->triangles_) {
    real const area = 0.5 * (at(tri[1]) - at(tri[0])).cross(at(tri[2]) - at(tri[0])).norm();
    for (int i : tri) c->vertexArea_[i] += area / 3;
  }
  for (std::size_t e = 0; e < c->edges_.size(); ++e) {
    auto const [a, b] = c->edges_[e];
    c->freeVertex_[a] = c->freeVertex_[b] = 0;
  }
  if (!c->triangles_.empty()) {
    DynamicArray<std::array<int, 2>> const triangleEdges = EdgesOf(c->triangles_);
    for (std::size_t e = 0; e < c->edges_.size(); ++e) {
      c->freeEdge_[e] = 0;
      // an edge's area: a third of each of its (at most two) triangles
      for (auto const& tri : c->triangles_) {
        int shared = 0;
        for (int i : tri) shared += (i == c->edges_[e][0] || i == c->edges_[e][1]);
        if (shared == 2)
          c->edgeArea_[e] += (at(tri[1]) - at(tri[0])).cross(at(tri[2]) - at(tri[0])).norm() / 6;
      }
    }
  }
  real const radius = std::max(c->thickness_, 1e-3);
  for (std::size_t e = 0; e < c->edges_.size(); ++e) {
    if (!c->freeEdge_[e]) continue;
    auto const [a, b] = c->edges_[e];
    real const length = (at(b) - at(a)).norm();
    c->edgeArea_[e] = 2 * radius * length;
    c->vertexArea_[a] += radius * length;
    c->vertexArea_[b] += radius * length;
  }
  for (int i = 0; i < n; ++i)
    if (c->freeVertex_[i]) c->vertexArea_[i] = M_PI * radius * radius;
  if (rigid)
    for (auto const& v : c->local_) c->radiusBound_ = std::max(c->radiusBound_, v.local.norm());
  c->id_ = nextId_++;
  colliders_.push_back(std::move(c));
  if (!CheckSeparated(static_cast<int>(colliders_.size()) - 1, error)) {
    colliders_.pop_back();
    --nextId_;
    PrepareVertices();
    return nullptr;
  }
  return colliders_.back().get();
}

bool ContactSystem::CheckSeparated(int index, Error& error) {
  PrepareVertices();
  bound_.assign(x_.size(), 0);
  pairs_.clear();
  Collider const& added = *colliders_[index];
  bool const moves = added.rigid_ || added.nodal_;
  for (int other = 0; other < index; ++other) {
    Collider const& c = *colliders_[other];
    bool const otherMoves = c.rigid_ || c.nodal_;
    if (moves == otherMoves) continue;  // only body–obstacle pairs touch so far
    if (!(added.group_ & c.mask_) || !(c.group_ & added.mask_)) continue;
    if (moves)
      AddPairs(index, other);
    else
      AddPairs(other, index);
  }
  for (Pair const& pair : pairs_) {
    real const gap = Gap(pair, x_, nullptr, nullptr);
    if (gap > 0) continue;
    Collider const& body = *colliders_[pair.body];
    Collider const& obstacle = *colliders_[pair.obstacle];
    error.Set(ErrorCode::InvalidArgument,
              "CreateCollider: collider " + std::to_string(body.id_) + " (" + std::string(ToString(body.shape_)) +
                  ") intersects collider " + std::to_string(obstacle.id_) + " (" +
                  std::string(ToString(obstacle.shape_)) + ") at " + Format(x_[pair.v[0]]) + " (gap " +
                  Format(gap) + " m, thicknesses included): colliders must start apart");
    pairs_.clear();
    return false;
  }
  pairs_.clear();
  return true;
}

void ContactSystem::PrepareVertices() {
  firstVertex_.assign(colliders_.size() + 1, 0);
  for (std::size_t c = 0; c < colliders_.size(); ++c)
    firstVertex_[c + 1] = firstVertex_[c] + static_cast<int>(colliders_[c]->local_.size());
  int const numVertices = firstVertex_.back();
  vertexCollider_.resize(numVertices);
  for (std::size_t c = 0; c < colliders_.size(); ++c)
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) vertexCollider_[i] = static_cast<int>(c);
  x_.resize(numVertices);
  trial_.resize(numVertices);
  displacement_.resize(numVertices);
  UpdatePositions(x_);
  x0_ = x_;
}

void ContactSystem::RemoveActor(ActorHandle actor) {
  std::erase_if(colliders_, [&](std::unique_ptr<Collider> const& c) { return !actor.IsNull() && c->actor_ == actor; });
  pairs_.clear();
  PrepareVertices();
}

Collider const* ContactSystem::GetCollider(int id) const {
  for (auto const& c : colliders_)
    if (c->id_ == id) return c.get();
  return nullptr;
}

// ---- positions ----

void ContactSystem::UpdatePositions(DynamicArray<Real3>& x) const {
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    Collider const& col = *colliders_[c];
    int const first = firstVertex_[c];
    if (col.rigid_) {
      Real33 const r = col.rigid_->GetRotation().toRotationMatrix();
      Real3 const t = col.rigid_->GetPosition();
      for (std::size_t i = 0; i < col.local_.size(); ++i) x[first + i] = t + r * col.local_[i].local;
    } else if (col.nodal_) {
      for (std::size_t i = 0; i < col.local_.size(); ++i) x[first + i] = col.nodal_->GetNodePosition(col.local_[i].node);
    } else {
      for (std::size_t i = 0; i < col.local_.size(); ++i) x[first + i] = col.local_[i].local;
    }
  }
}

// ---- candidates ----

void ContactSystem::BeginStage(StageContext const& stage) {
  stage_ = stage;
  PrepareVertices();
  int const numVertices = firstVertex_.back();
  // each vertex's displacement bound for the stage: twice the free motion
  // (velocity and gravity over the stage) of the body's fastest vertex, plus
  // d̂. The body's fastest, not the vertex's own: a vertex at rest is pushed
  // by the rest of its body (a ball's bottom spreads as its top lands on it)
  real const h = stage.coefficients.duration;
  real const dhat = params_.activationDistance;
  bound_.assign(numVertices, 0);
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    Collider const& col = *colliders_[c];
    if (!col.rigid_ && !col.nodal_) continue;
    real speed = 0;
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) {
      if (col.rigid_) {
        Real3 const arm = x_[i] - col.rigid_->GetPosition();
        speed = std::max(speed, (col.rigid_->GetLinearVelocity() + col.rigid_->GetAngularVelocity().cross(arm)).norm());
      } else {
        speed = std::max(speed, col.nodal_->GetNodeVelocity(col.local_[i - firstVertex_[c]].node).norm());
      }
    }
    real const bound = 2 * (speed * h + stage.gravity.norm() * h * h) + dhat;
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) bound_[i] = bound;
  }
  FindCandidates();
  for (Pair& pair : pairs_) LagFriction(pair);
}

void ContactSystem::FindCandidates() {
  pairs_.clear();
  for (std::size_t a = 0; a < colliders_.size(); ++a) {
    Collider const& body = *colliders_[a];
    if (!body.rigid_ && !body.nodal_) continue;
    for (std::size_t b = 0; b < colliders_.size(); ++b) {
      Collider const& obstacle = *colliders_[b];
      if (obstacle.rigid_ || obstacle.nodal_) continue;  // body–body contact: not yet
      if (!(body.group_ & obstacle.mask_) || !(obstacle.group_ & body.mask_)) continue;
      AddPairs(static_cast<int>(a), static_cast<int>(b));
    }
  }
}

void ContactSystem::AddPairs(int bodyIndex, int obstacleIndex) {
  Collider const& body = *colliders_[bodyIndex];
  Collider const& obstacle = *colliders_[obstacleIndex];
  int const fb = firstVertex_[bodyIndex], fo = firstVertex_[obstacleIndex];
  real const dhat = params_.activationDistance;
  real const thickness = body.thickness_ + obstacle.thickness_;
  real const mu = std::sqrt(body.friction_ * obstacle.friction_);
  auto add = [&](PairKind kind, std::array<int, 4> v, std::array<bool, 4> onBody, int count, real weight) {
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
    pairs_.push_back(pair);
  };
  // the box of a set of vertices over the stage: start ± bound
  auto reach = [&](int i) { return bound_[i]; };
  auto near = [&](std::initializer_list<int> a, std::initializer_list<int> b) {
    Eigen::AlignedBox<real, 3> boxA, boxB;
    real ra = 0, rb = 0;
    for (int i : a) {
      boxA.extend(x_[i]);
      ra = std::max(ra, reach(i));
    }
    for (int i : b) {
      boxB.extend(x_[i]);
      rb = std::max(rb, reach(i));
    }
    real const margin = dhat + thickness + ra + rb;
    return (boxA.min().array() - margin <= boxB.max().array()).all() &&
           (boxB.min().array() - margin <= boxA.max().array()).all();
  };
  int const nb = static_cast<int>(body.local_.size());
  if (obstacle.shape_ == ShapeType::Plane) {
    for (int i = 0; i < nb; ++i) {
      // vertices on a primitive only (a solid's interior nodes never touch)
      bool const used = body.freeVertex_[i] ? body.shape_ != ShapeType::Surface || body.edges_.empty() : true;
      if (!used || body.vertexArea_[i] <= 0) continue;
      real const gap = obstacle.planeNormal_.dot(x_[fb + i]) - obstacle.planeOffset_ - thickness;
      if (gap < dhat + reach(fb + i)) add(PairKind::PlaneVertex, {fb + i, -1, -1, -1}, {true, false, false, false}, 1,
                                          body.vertexArea_[i]);
    }
    return;
  }
  // body vertices against obstacle triangles, obstacle vertices against body triangles
  for (int i = 0; i < nb; ++i) {
    if (body.vertexArea_[i] <= 0) continue;
    for (auto const& t : obstacle.triangles_)
      if (near({fb + i}, {fo + t[0], fo + t[1], fo + t[2]}))
        add(PairKind::PointTriangle, {fb + i, fo + t[0], fo + t[1], fo + t[2]}, {true, false, false, false}, 4,
            body.vertexArea_[i]);
  }
  for (std::size_t i = 0; i < obstacle.local_.size(); ++i) {
    int const vi = fo + static_cast<int>(i);
    for (auto const& t : body.triangles_)
      if (near({vi}, {fb + t[0], fb + t[1], fb + t[2]}))
        add(PairKind::PointTriangle, {vi, fb + t[0], fb + t[1], fb + t[2]}, {false, true, true, true}, 4,
            std::max(obstacle.vertexArea_[i], (x_[fb + t[1]] - x_[fb + t[0]]).cross(x_[fb + t[2]] - x_[fb + t[0]]).norm() / 2));
  }
  // edges against edges
  for (std::size_t e = 0; e < body.edges_.size(); ++e) {
    auto const [a0, a1] = body.edges_[e];
    for (std::size_t f = 0; f < obstacle.edges_.size(); ++f) {
      auto const [b0, b1] = obstacle.edges_[f];
      if (near({fb + a0, fb + a1}, {fo + b0, fo + b1}))
        add(PairKind::EdgeEdge, {fb + a0, fb + a1, fo + b0, fo + b1}, {true, true, false, false}, 4,
            std::max(body.edgeArea_[e], obstacle.edgeArea_[f]));
    }
  }
  // points against free edges (rods, capsules) and free points (spheres)
  for (int i = 0; i < nb; ++i) {
    for (std::size_t f = 0; f < obstacle.edges_.size(); ++f) {
      // a vertex on an edge is covered by edge–edge (its point–edge types)
      if (!obstacle.freeEdge_[f] || !body.freeVertex_[i]) continue;
      auto const [b0, b1] = obstacle.edges_[f];
      if (near({fb + i}, {fo + b0, fo + b1}))
        add(PairKind::PointEdge, {fb + i, fo + b0, fo + b1, -1}, {true, false, false, false}, 3, body.vertexArea_[i]);
    }
  }
  for (std::size_t i = 0; i < obstacle.local_.size(); ++i) {
    if (!obstacle.freeVertex_[i]) continue;
    int const vi = fo + static_cast<int>(i);
    for (std::size_t e = 0; e < body.edges_.size(); ++e) {
      if (!body.freeEdge_[e]) continue;
      auto const [a0, a1] = body.edges_[e];
      if (near({vi}, {fb + a0, fb + a1}))
        add(PairKind::PointEdge, {vi, fb + a0, fb + a1, -1}, {false, true, true, false}, 3, body.edgeArea_[e]);
    }
    for (int j = 0; j < nb; ++j)
      if (body.freeVertex_[j] && near({vi}, {fb + j}))
        add(PairKind::PointPoint, {fb + j, vi, -1, -1}, {true, false, false, false}, 2,
            std::max(body.vertexArea_[j], obstacle.vertexArea_[i]));
  }
}

// ---- geometry of one pair ----

real ContactSystem::Gap(Pair const& pair, DynamicArray<Real3> const& x, Vector12* gradient, Matrix12* hessian) const {
  if (pair.kind == PairKind::PlaneVertex) {
    Collider const& plane = *colliders_[pair.obstacle];
    if (gradient) {
      gradient->setZero();
      gradient->head<3>() = plane.planeNormal_;
    }
    if (hessian) hessian->setZero();
    return plane.planeNormal_.dot(x[pair.v[0]]) - plane.planeOffset_ - pair.thickness;
  }
  auto const& v = pair.v;
  real d2 = 0;
  Vector12 g = Vector12::Zero();
  Matrix12 H = Matrix12::Zero();
  bool const derivatives = gradient || hessian;
  switch (pair.kind) {
    case PairKind::PointTriangle: {
      auto const type = contact::PointTriangleDistanceType(x[v[0]], x[v[1]], x[v[2]], x[v[3]]);
      d2 = contact::PointTriangleDistance2(x[v[0]], x[v[1]], x[v[2]], x[v[3]], type);
      if (derivatives) {
        g = contact::PointTriangleDistance2Gradient(x[v[0]], x[v[1]], x[v[2]], x[v[3]], type);
        if (hessian) H = contact::PointTriangleDistance2Hessian(x[v[0]], x[v[1]], x[v[2]], x[v[3]], type);
      }
      break;
    }
    case PairKind::EdgeEdge: {
      auto const type = contact::EdgeEdgeDistanceType(x[v[0]], x[v[1]], x[v[2]], x[v[3]]);
      d2 = contact::EdgeEdgeDistance2(x[v[0]], x[v[1]], x[v[2]], x[v[3]], type);
      if (derivatives) {
        g = contact::EdgeEdgeDistance2Gradient(x[v[0]], x[v[1]], x[v[2]], x[v[3]], type);
        if (hessian) H = contact::EdgeEdgeDistance2Hessian(x[v[0]], x[v[1]], x[v[2]], x[v[3]], type);
      }
      break;
    }
    case PairKind::PointEdge: {
      auto const type = contact::PointEdgeDistanceType(x[v[0]], x[v[1]], x[v[2]]);
      d2 = contact::PointEdgeDistance2(x[v[0]], x[v[1]], x[v[2]], type);
      if (derivatives) {
        g.head<9>() = contact::PointEdgeDistance2Gradient(x[v[0]], x[v[1]], x[v[2]], type);
        if (hessian) H.topLeftCorner<9, 9>() = contact::PointEdgeDistance2Hessian(x[v[0]], x[v[1]], x[v[2]], type);
      }
      break;
    }
    case PairKind::PointPoint: {
      d2 = contact::PointPointDistance2(x[v[0]], x[v[1]]);
      if (derivatives) {
        g.head<6>() = contact::PointPointDistance2Gradient(x[v[0]], x[v[1]]);
        if (hessian) H.topLeftCorner<6, 6>() = contact::PointPointDistance2Hessian(x[v[0]], x[v[1]]);
      }
      break;
    }
    case PairKind::PlaneVertex: break;
  }
  // d = sqrt(d²) − thickness
  real const d = std::sqrt(d2);
  if (gradient || hessian) {
    real const inv = d > 0 ? 1 / (2 * d) : 0;
    if (gradient) *gradient = inv * g;
    if (hessian) *hessian = inv * H - (2 * inv * inv * inv) * (g * g.transpose());
  }
  return d - pair.thickness;
}

void ContactSystem::LagFriction(Pair& pair) const {
  // the normal force at the stage start, and the tangent plane there
  Vector12 grad;
  real const d = Gap(pair, x0_, &grad, nullptr);
  real const dhat = params_.activationDistance;
  pair.lambda = 0;
  pair.gamma = {0, 0, 0, 0};
  pair.basis.setZero();
  if (!(d > 0) || d >= dhat || pair.mu == 0) return;
  real const kw = params_.stiffness * pair.weight;
  pair.lambda = -kw * contact::BarrierDerivative(d / dhat);
  // the normal: the gap's gradient on the first vertex, and the weights of
  // each vertex in the relative displacement of the closest points: the
  // gradient of d w.r.t. a vertex is (its weight)·n
  Real3 n = Real3::Zero();
  for (int k = 0; k < pair.numVertices; ++k) {
    Real3 const gk = grad.segment<3>(3 * k);
    if (gk.norm() > n.norm()) n = gk.normalized() * (pair.kind == PairKind::PlaneVertex || k == 0 ? 1 : 1);
  }
  // orient n from the obstacle side to the body side: along the body's gradient
  Real3 bodyGrad = Real3::Zero();
  for (int k = 0; k < pair.numVertices; ++k)
    if (pair.onBody[k]) bodyGrad += grad.segment<3>(3 * k);
  if (bodyGrad.norm() == 0) return;
  n = bodyGrad.normalized();
  pair.basis = TangentBasis(n);
  for (int k = 0; k < pair.numVertices; ++k) {
    // ∂d/∂x_k = γ_k n for the closest points' relative displacement
    pair.gamma[k] = grad.segment<3>(3 * k).dot(n);
  }
  auto const it = anchors_.find(pair.key);
  pair.slip0 = it == anchors_.end() ? Real3::Zero() : Real3(pair.basis * (pair.basis.transpose() * it->second));
}

real ContactSystem::PairEnergy(Pair const& pair) const {
  real const dhat = params_.activationDistance;
  real const d = Gap(pair, x_, nullptr, nullptr);
  if (!(d > 0)) return std::numeric_limits<real>::infinity();
  real energy = 0;
  if (d < dhat) energy += params_.stiffness * pair.weight * dhat * contact::Barrier(d / dhat);
  if (pair.lambda > 0) {
    Real3 slip = pair.slip0;
    for (int k = 0; k < pair.numVertices; ++k) slip += pair.gamma[k] * (x_[pair.v[k]] - x0_[pair.v[k]]);
    Eigen::Matrix<real, 2, 1> const u = pair.basis.transpose() * slip;
    energy += pair.mu * pair.lambda * contact::FrictionRamp(u.norm(), params_.frictionRampWidth);
  }
  return energy;
}

// ---- the stage term ----

void ContactSystem::PairDofs(Pair const& pair, DynamicArray<int>& dofs) const {
  Collider const& body = *colliders_[pair.body];
  if (body.rigid_) {
    int const o = body.rigid_->GetDofOffset();
    for (int k = 0; k < 6; ++k) dofs.push_back(o + k);
    return;
  }
  int const o = body.nodal_->GetDofOffset(), stride = body.nodal_->GetNodeDofStride();
  for (int k = 0; k < pair.numVertices; ++k) {
    if (!pair.onBody[k]) continue;
    int const node = body.local_[pair.v[k] - firstVertex_[pair.body]].node;
    for (int j = 0; j < 3; ++j) dofs.push_back(o + stride * node + j);
  }
}

void ContactSystem::AppendStageContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const {
  for (Pair const& pair : pairs_) {
    dofLists.emplace_back();
    PairDofs(pair, dofLists.back());
  }
}

void ContactSystem::AddEnergy(HessianAssembler const&, int, EnergySum& sum) const {
  UpdatePositions(x_);
  for (Pair const& pair : pairs_) sum.Add(PairEnergy(pair));
}

void ContactSystem::AddGradientAndHessian(HessianAssembler& assembler, int, AssemblyOptions const& options) const {
  UpdatePositions(x_);
  real const dhat = params_.activationDistance;
  real const kw0 = params_.stiffness;
  using DofVector = Eigen::Matrix<real, Eigen::Dynamic, 1, 0, 12, 1>;
  using DofMatrix = Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic, 0, 12, 12>;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    Pair const& pair = pairs_[p];
    int const contributor = options.firstStageContributor + static_cast<int>(p);
    // the energy's gradient and Hessian w.r.t. the pair's vertex positions
    Vector12 gd;
    Matrix12 Hd;
    real const d = Gap(pair, x_, &gd, &Hd);
    Vector12 g = Vector12::Zero();
    Matrix12 H = Matrix12::Zero();
    int const n = 3 * pair.numVertices;
    if (d > 0 && d < dhat) {
      real const kw = kw0 * pair.weight;
      real const b1 = kw * contact::BarrierDerivative(d / dhat);
      real const b2 = kw * contact::BarrierSecondDerivative(d / dhat) / dhat;
      g += b1 * gd;
      H += b2 * gd * gd.transpose() + b1 * Hd;
    }
    if (pair.lambda > 0) {
      Real3 slip = pair.slip0;
      for (int k = 0; k < pair.numVertices; ++k) slip += pair.gamma[k] * (x_[pair.v[k]] - x0_[pair.v[k]]);
      Eigen::Matrix<real, 2, 1> const u = pair.basis.transpose() * slip;
      contact::TangentialFriction const friction =
          contact::EvaluateTangentialFriction(u, pair.mu * pair.lambda, params_.frictionRampWidth);
      Real3 const f3 = pair.basis * friction.gradient;
      Real33 const k3 = pair.basis * friction.hessian * pair.basis.transpose();
      for (int a = 0; a < pair.numVertices; ++a) {
        g.segment<3>(3 * a) += pair.gamma[a] * f3;
        for (int b = 0; b < pair.numVertices; ++b) H.block<3, 3>(3 * a, 3 * b) += pair.gamma[a] * pair.gamma[b] * k3;
      }
    }
    if (g.head(n).isZero(0) && H.topLeftCorner(n, n).isZero(0)) continue;
    if (n == 3) {
      Real33 const h3 = H.topLeftCorner<3, 3>();
      Eigen::SelfAdjointEigenSolver<Real33> eigen(h3);
      H.topLeftCorner<3, 3>() = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0).asDiagonal() *
                                eigen.eigenvectors().transpose();
    } else if (n == 6) {
      H.topLeftCorner<6, 6>() = contact::ProjectToPsd<6>(H.topLeftCorner<6, 6>());
    } else if (n == 9) {
      H.topLeftCorner<9, 9>() = contact::ProjectToPsd<9>(H.topLeftCorner<9, 9>());
    } else {
      H = contact::ProjectToPsd<12>(H);
    }
    // through the body's DoFs
    Collider const& body = *colliders_[pair.body];
    DofVector gq;
    DofMatrix Hq;
    if (body.rigid_) {
      Eigen::Matrix<real, 12, 6> J = Eigen::Matrix<real, 12, 6>::Zero();
      Real3 const c = body.rigid_->GetPosition();
      Real33 curvature = Real33::Zero();
      for (int k = 0; k < pair.numVertices; ++k) {
        if (!pair.onBody[k]) continue;
        Real3 const arm = x_[pair.v[k]] - c;
        J.block<3, 3>(3 * k, 0) = Real33::Identity();
        J.block<3, 3>(3 * k, 3) = -Hat(arm);
        curvature += RotatedVectorCurvature(g.segment<3>(3 * k), arm);
      }
      gq = J.topRows(n).transpose() * g.head(n);
      Hq = J.topRows(n).transpose() * H.topLeftCorner(n, n) * J.topRows(n);
      if (!options.projectHessian) Hq.bottomRightCorner<3, 3>() += curvature;
    } else {
      Real33 const r = body.nodal_->GetTransformRotation().toRotationMatrix();
      int m = 0;
      std::array<int, 4> slot{};
      for (int k = 0; k < pair.numVertices; ++k)
        if (pair.onBody[k]) slot[m++] = k;
      gq.resize(3 * m);
      Hq.resize(3 * m, 3 * m);
      for (int a = 0; a < m; ++a) {
        gq.segment<3>(3 * a) = r.transpose() * g.segment<3>(3 * slot[a]);
        for (int b = 0; b < m; ++b)
          Hq.block<3, 3>(3 * a, 3 * b) = r.transpose() * H.block<3, 3>(3 * slot[a], 3 * slot[b]) * r;
      }
    }
    assembler.AddDynamicGradient(contributor, gq);
    assembler.AddDynamicBlock(contributor, Hq);
  }
}

// ---- the safe step ----

real ContactSystem::RigidPairCcd(Pair const& pair, Span<real const> delta, real tMax) const {
  // conservative advancement on the exact arcs x(α) = c + α δt + Exp(α δθ) a:
  // every point of the body moves at most L = |δt| + |δθ| max|a| per unit α,
  // so advancing by (gap − target)/L never passes the target gap
  Collider const& body = *colliders_[pair.body];
  int const o = body.rigid_->GetDofOffset();
  Real3 const dt(delta[o], delta[o + 1], delta[o + 2]), dr(delta[o + 3], delta[o + 4], delta[o + 5]);
  Real3 const c = body.rigid_->GetPosition();
  real armBound = 0;
  for (int k = 0; k < pair.numVertices; ++k)
    if (pair.onBody[k]) armBound = std::max(armBound, (x_[pair.v[k]] - c).norm());
  real const speed = dt.norm() + dr.norm() * armBound;
  real const gap0 = Gap(pair, x_, nullptr, nullptr);
  if (!(gap0 > 0)) return 0;
  if (speed == 0) return tMax;
  real const target = (1 - contact::kCcdRescale) * gap0;
  real const stop = contact::kCcdStopFraction * contact::kCcdRescale * gap0;
  for (int k = 0; k < pair.numVertices; ++k) trial_[pair.v[k]] = x_[pair.v[k]];
  real t = 0;
  for (int iteration = 0; iteration < contact::kCcdMaxIterations; ++iteration) {
    Real33 const turn = ExpMatrix(t * dr);
    for (int k = 0; k < pair.numVertices; ++k)
      if (pair.onBody[k]) trial_[pair.v[k]] = c + t * dt + turn * (x_[pair.v[k]] - c);
    real const gap = Gap(pair, trial_, nullptr, nullptr);
    if (gap - target <= stop) return t;
    t += (gap - target) / speed;
    if (t >= tMax) return tMax;
  }
  return t;
}

real ContactSystem::LargestSafeStep(Span<real const> delta, real alpha) const {
  UpdatePositions(x_);
  // each vertex's displacement along δ: exact for nodes (linear in α); a
  // rigid body's vertices move on arcs, bounded by the chord's rate for the
  // displacement bound and checked on the arcs by RigidPairCcd
  for (std::size_t c = 0; c < colliders_.size(); ++c) {
    Collider const& col = *colliders_[c];
    for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) displacement_[i].setZero();
    if (col.rigid_) {
      int const o = col.rigid_->GetDofOffset();
      Real3 const dt(delta[o], delta[o + 1], delta[o + 2]), dr(delta[o + 3], delta[o + 4], delta[o + 5]);
      Real3 const center = col.rigid_->GetPosition();
      for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i)
        displacement_[i] = dt + dr.cross(x_[i] - center);
    } else if (col.nodal_) {
      Real33 const r = col.nodal_->GetTransformRotation().toRotationMatrix();
      int const o = col.nodal_->GetDofOffset(), stride = col.nodal_->GetNodeDofStride();
      for (int i = firstVertex_[c]; i < firstVertex_[c + 1]; ++i) {
        int const dof = o + stride * col.local_[i - firstVertex_[c]].node;
        displacement_[i] = r * Real3(delta[dof], delta[dof + 1], delta[dof + 2]);
      }
    }
  }
  real safe = alpha;
  // the stage's displacement bound of every vertex
  for (std::size_t i = 0; i < x_.size(); ++i) {
    real const step = displacement_[i].norm();
    if (step == 0) continue;
    real const room = bound_[i] - (x_[i] - x0_[i]).norm();
    safe = std::min(safe, std::max(room, real(0)) / step);
  }
  // continuous collision detection of every candidate along the step
  for (Pair const& pair : pairs_) {
    auto const& v = pair.v;
    Collider const& body = *colliders_[pair.body];
    real t = 1;
    if (body.rigid_) {
      safe = RigidPairCcd(pair, delta, safe);
      continue;
    } else {
      auto dx = [&](int k) -> Real3 { return displacement_[v[k]] * safe; };
      real const thickness = pair.thickness;
      switch (pair.kind) {
        case PairKind::PlaneVertex: {
          Collider const& plane = *colliders_[pair.obstacle];
          t = contact::PointPlaneCcd(x_[v[0]], dx(0), thickness, plane.planeNormal_, plane.planeOffset_, 0, 1);
          break;
        }
        case PairKind::PointTriangle:
          t = contact::PointTriangleCcd(x_[v[0]], x_[v[1]], x_[v[2]], x_[v[3]], dx(0), dx(1), dx(2), dx(3), thickness,
                                        1);
          break;
        case PairKind::EdgeEdge:
          t = contact::EdgeEdgeCcd(x_[v[0]], x_[v[1]], x_[v[2]], x_[v[3]], dx(0), dx(1), dx(2), dx(3), thickness, 1);
          break;
        case PairKind::PointEdge:
          t = contact::PointEdgeCcd(x_[v[0]], x_[v[1]], x_[v[2]], dx(0), dx(1), dx(2), thickness, 1);
          break;
        case PairKind::PointPoint: t = contact::PointPointCcd(x_[v[0]], x_[v[1]], dx(0), dx(1), thickness, 1); break;
      }
    }
    safe *= t;
  }
  return safe;
}

bool ContactSystem::AcceptsFirstIterate() const {
  UpdatePositions(x_);
  for (std::size_t i = 0; i < x_.size(); ++i)
    if ((x_[i] - x0_[i]).norm() > bound_[i]) return false;
  for (Pair const& pair : pairs_) {
    auto const& v = pair.v;
    auto dx = [&](int k) -> Real3 { return x_[v[k]] - x0_[v[k]]; };
    real t = 1;
    switch (pair.kind) {
      case PairKind::PlaneVertex: {
        Collider const& plane = *colliders_[pair.obstacle];
        t = contact::PointPlaneCcd(x0_[v[0]], dx(0), pair.thickness, plane.planeNormal_, plane.planeOffset_, 0, 1);
        break;
      }
      case PairKind::PointTriangle:
        t = contact::PointTriangleCcd(x0_[v[0]], x0_[v[1]], x0_[v[2]], x0_[v[3]], dx(0), dx(1), dx(2), dx(3),
                                      pair.thickness, 1);
        break;
      case PairKind::EdgeEdge:
        t = contact::EdgeEdgeCcd(x0_[v[0]], x0_[v[1]], x0_[v[2]], x0_[v[3]], dx(0), dx(1), dx(2), dx(3),
                                 pair.thickness, 1);
        break;
      case PairKind::PointEdge:
        t = contact::PointEdgeCcd(x0_[v[0]], x0_[v[1]], x0_[v[2]], dx(0), dx(1), dx(2), pair.thickness, 1);
        break;
      case PairKind::PointPoint: t = contact::PointPointCcd(x0_[v[0]], x0_[v[1]], dx(0), dx(1), pair.thickness, 1); break;
    }
    if (t < 1) return false;
  }
  return true;
}

// ---- the stage end ----

void ContactSystem::EndStage() {
  UpdatePositions(x_);
  std::unordered_map<std::uint64_t, Real3> anchors;
  active_ = 0;
  minDistance_ = std::numeric_limits<real>::infinity();
  real const g = params_.frictionRampWidth;
  for (Pair const& pair : pairs_) {
    real const d = Gap(pair, x_, nullptr, nullptr);
    minDistance_ = std::min(minDistance_, d);
    if (d < params_.activationDistance) ++active_;
    if (pair.lambda <= 0) continue;
    // the slip from the anchor; a sliding contact drags its anchor to ḡ behind
    Real3 slip = pair.slip0;
    for (int k = 0; k < pair.numVertices; ++k) slip += pair.gamma[k] * (x_[pair.v[k]] - x0_[pair.v[k]]);
    slip = pair.basis * (pair.basis.transpose() * slip);
    real const norm = slip.norm();
    if (norm > g) slip *= g / norm;
    anchors[pair.key] = slip;
  }
  anchors_ = std::move(anchors);
}

void ContactSystem::GetContacts(DynamicArray<ContactInfo>& contacts) const {
  contacts.clear();
  DynamicArray<Real3> x(x_.size());
  UpdatePositions(x);
  real const dhat = params_.activationDistance;
  for (Pair const& pair : pairs_) {
    Vector12 grad;
    real const d = Gap(pair, x, &grad, nullptr);
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
    info.point = obstacleWeight > 0 ? Real3(point / obstacleWeight) : Real3(x[pair.v[0]] - (d + pair.thickness) * info.normal);
    info.distance = d;
    info.normalForce = -params_.stiffness * pair.weight * contact::BarrierDerivative(d / dhat);
    if (pair.lambda > 0) {
      Real3 slip = pair.slip0;
      for (int k = 0; k < pair.numVertices; ++k) slip += pair.gamma[k] * (x[pair.v[k]] - x0_[pair.v[k]]);
      Eigen::Matrix<real, 2, 1> const u = pair.basis.transpose() * slip;
      contact::TangentialFriction const friction =
          contact::EvaluateTangentialFriction(u, pair.mu * pair.lambda, params_.frictionRampWidth);
      info.frictionForce = -(pair.basis * friction.gradient);
    }
    contacts.push_back(info);
  }
}

}  // namespace internal
}  // namespace superdex
