#include <superdex/actors/articulated_actor.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/so3.h>
#include <superdex/core/symmetric_eigen.h>
#include <superdex/core/validate.h>
#include <superdex/linsolve/linear_solver.h>

namespace superdex {

namespace {
using Matrix6 = Eigen::Matrix<real, 6, 6>;
using Vector6 = Eigen::Matrix<real, 6, 1>;
/// Up to 6 spatial columns (one joint's), without heap storage.
using SpatialColumns = Eigen::Matrix<real, 6, Eigen::Dynamic, 0, 6, 6>;

std::string LinkField(std::size_t link, std::string_view field) {
  return "ArticulatedActorParams.links[" + std::to_string(link) + "]." + std::string(field);
}

/// Spatial inertia about the world origin, coordinates (ω, v_O), of a body
/// whose energy Hessian is `rotation` (3×3, world increments) and w m I
/// (translation of its centre c): Xᵀ G X with v_c = v_O − Hat(c) ω.
Matrix6 SpatialStiffness(Real33 const& rotation, real translation, Real3 const& c) {
  Real33 const hatC = Hat(c);
  Matrix6 k;
  k.topLeftCorner<3, 3>() = rotation + translation * hatC.transpose() * hatC;
  k.topRightCorner<3, 3>() = -translation * hatC.transpose();
  k.bottomLeftCorner<3, 3>() = -translation * hatC;
  k.bottomRightCorner<3, 3>() = translation * Real33::Identity();
  return k;
}
/// The kinematic curvature of the link poses against wrenches with sums
/// P = Σ c fᵀ, F = Σ f, T = Σ τ, as a 6×6 operator: for a DoF a upstream of
/// a DoF b, the Hessian term s_aᵀ C s_b (docs/articulated.md). Its angular
/// row is (P − tr P·I − ½[T]×, −[F]×), its linear row zero.
Matrix6 Curvature(Real33 const& p, Real3 const& f, Real3 const& tau) {
  Matrix6 c = Matrix6::Zero();
  c.topLeftCorner<3, 3>() = p - p.trace() * Real33::Identity() - 0.5 * Hat(tau);
  c.topRightCorner<3, 3>() = -Hat(f);
  return c;
}
}  // namespace

std::string_view ToString(ArticulatedBlockSolve solve) {
  switch (solve) {
    case ArticulatedBlockSolve::Tree: return "Tree";
    case ArticulatedBlockSolve::Dense: return "Dense";
  }
  return "Unknown";
}

std::string_view ToString(JointType type) {
  switch (type) {
    case JointType::Fixed: return "Fixed";
    case JointType::Revolute: return "Revolute";
    case JointType::Prismatic: return "Prismatic";
    case JointType::Spherical: return "Spherical";
    case JointType::Free: return "Free";
  }
  return "Unknown";
}

int JointDofs(JointType type) {
  switch (type) {
    case JointType::Fixed: return 0;
    case JointType::Revolute:
    case JointType::Prismatic: return 1;
    case JointType::Spherical: return 3;
    case JointType::Free: return 6;
  }
  return 0;
}

bool ArticulatedActor::LinkFromParams(int i, ArticulatedLinkParams const& p, Link& l, Error& error) {
  using namespace internal;
  if (i == 0 ? p.parent != -1 : (p.parent < 0 || p.parent >= i)) {
    error.Set(ErrorCode::InvalidArgument,
              LinkField(i, "parent") + (i == 0 ? " must be -1 (the root joint attaches to the world), got "
                                               : " must name an earlier link, in [0, " + std::to_string(i) +
                                                     "), got ") +
                  std::to_string(p.parent));
    return false;
  }
  int const type = static_cast<int>(p.joint);
  if (type < static_cast<int>(JointType::Fixed) || type > static_cast<int>(JointType::Free)) {
    error.Set(ErrorCode::InvalidArgument, LinkField(i, "joint") + " is not a JointType (" + std::to_string(type) + ")");
    return false;
  }
  if (!CheckFinite(p.axis, LinkField(i, "axis"), error) ||
      !CheckFinite(p.parentToJointPosition, LinkField(i, "parentToJointPosition"), error) ||
      !CheckUnitQuat(p.parentToJointRotation, LinkField(i, "parentToJointRotation"), error) ||
      !CheckFinite(p.jointToChildPosition, LinkField(i, "jointToChildPosition"), error) ||
      !CheckUnitQuat(p.jointToChildRotation, LinkField(i, "jointToChildRotation"), error) ||
      !CheckPositive(p.mass, LinkField(i, "mass"), error) ||
      !CheckPositive(p.inertia, LinkField(i, "inertia"), error) ||
      !CheckFinite(p.centerOfMass, LinkField(i, "centerOfMass"), error) ||
      !CheckNonNegative(p.armature, LinkField(i, "armature"), error) ||
      !CheckNonNegative(p.damping, LinkField(i, "damping"), error))
    return false;
  if ((p.joint == JointType::Revolute || p.joint == JointType::Prismatic) && !(p.axis.norm() > 1e-12)) {
    error.Set(ErrorCode::InvalidArgument, LinkField(i, "axis") + " must be non-zero for a " +
                                              std::string(ToString(p.joint)) + " joint, got " + Format(p.axis));
    return false;
  }
  if (p.joint == JointType::Free && i != 0) {
    error.Set(ErrorCode::InvalidArgument,
              LinkField(i, "joint") + " is Free: only the root joint may be free (a floating base)");
    return false;
  }
  int const dofs = JointDofs(p.joint);
  for (auto const* state : {&p.initialPosition, &p.initialVelocity}) {
    if (!state->empty() && static_cast<int>(state->size()) != dofs) {
      error.Set(ErrorCode::InvalidArgument,
                LinkField(i, state == &p.initialPosition ? "initialPosition" : "initialVelocity") +
                    " must be empty or hold " + std::to_string(dofs) + " entries (a " +
                    std::string(ToString(p.joint)) + " joint), got " + std::to_string(state->size()));
      return false;
    }
    for (real v : *state)
      if (!std::isfinite(v)) {
        error.Set(ErrorCode::InvalidArgument,
                  LinkField(i, state == &p.initialPosition ? "initialPosition" : "initialVelocity") +
                      " is not finite");
        return false;
      }
  }
  // a rotation vector whose norm overflows has no angle (Exp gives NaN)
  int const rotationStart = p.joint == JointType::Spherical ? 0 : p.joint == JointType::Free ? 3 : -1;
  if (rotationStart >= 0 && !p.initialPosition.empty()) {
    Real3 const phi(p.initialPosition[rotationStart], p.initialPosition[rotationStart + 1],
                    p.initialPosition[rotationStart + 2]);
    if (!std::isfinite(phi.norm())) {
      error.Set(ErrorCode::InvalidArgument,
                LinkField(i, "initialPosition") + "[" + std::to_string(rotationStart) + ".." +
                    std::to_string(rotationStart + 2) + "] = " + Format(phi) +
                    " is a rotation vector whose angle (its norm) overflows; give the angle in radians");
      return false;
    }
  }
  l.parent = p.parent;
  l.joint = p.joint;
  // scaled first, so that an axis like 1e200 does not overflow its norm
  real const axisScale = p.axis.cwiseAbs().maxCoeff();
  l.axis = axisScale > 0 ? Real3((p.axis / axisScale).normalized()) : Real3::UnitZ();
  l.parentToJointPosition = p.parentToJointPosition;
  l.parentToJointRotation = p.parentToJointRotation.normalized();
  l.jointToChildPosition = p.jointToChildPosition;
  l.jointToChildRotation = p.jointToChildRotation.normalized();
  l.mass = p.mass;
  l.inertia = p.inertia;
  l.centerOfMass = p.centerOfMass;
  l.armature = p.armature;
  l.damping = p.damping;
  l.numDofs = dofs;
  return true;
}

std::unique_ptr<ArticulatedActor> ArticulatedActor::Create(ArticulatedActorParams const& params, Error& error) {
  using namespace internal;
  int const numLinks = static_cast<int>(params.links.size());
  if (numLinks < 1) {
    error.Set(ErrorCode::InvalidArgument, "ArticulatedActorParams.links needs at least one link, got none");
    return nullptr;
  }
  DynamicArray<Link> links(numLinks);
  int numDofs = 0;
  for (int i = 0; i < numLinks; ++i) {
    if (!LinkFromParams(i, params.links[i], links[i], error)) return nullptr;
    links[i].dofStart = numDofs;
    numDofs += links[i].numDofs;
  }
  if (numDofs == 0) {
    error.Set(ErrorCode::InvalidArgument,
              "ArticulatedActorParams.links: every joint is Fixed; an articulated actor needs at least one DoF");
    return nullptr;
  }

  if (params.blockSolve != ArticulatedBlockSolve::Tree && params.blockSolve != ArticulatedBlockSolve::Dense) {
    error.Set(ErrorCode::InvalidArgument, "ArticulatedActorParams.blockSolve is not an ArticulatedBlockSolve (" +
                                              std::to_string(static_cast<int>(params.blockSolve)) + ")");
    return nullptr;
  }

  if (params.blockSolve == ArticulatedBlockSolve::Dense && numDofs > kDenseSolverMaxUnknowns) {
    // the dense block's modified Cholesky is O(n³) per Newton iteration
    // (3.1 s per step at 2,400 DoFs, minutes at 5,100)
    error.Set(ErrorCode::InvalidArgument,
              "ArticulatedActorParams.blockSolve = Dense takes at most kDenseSolverMaxUnknowns = " +
                  std::to_string(kDenseSolverMaxUnknowns) + " DoFs (the dense block is factorized in O(n³) every "
                  "Newton iteration), got " + std::to_string(numDofs) + " DoFs; use Tree");
    return nullptr;
  }
  std::unique_ptr<ArticulatedActor> actor(new ArticulatedActor(numDofs));
  ArticulatedActor& a = *actor;
  a.links_ = std::move(links);
  a.blockSolve_ = params.blockSolve;
  a.extrapolateFirstIterate_ = params.extrapolateFirstIterate;
  a.dofLink_.resize(numDofs);
  for (int i = 0; i < numLinks; ++i) {
    Link const& l = a.links_[i];
    a.linkParent_.push_back(l.parent);
    a.linkDofStart_.push_back(l.dofStart);
    a.linkNumDofs_.push_back(l.numDofs);
    for (int k = l.dofStart; k < l.dofStart + l.numDofs; ++k) a.dofLink_[k] = i;
  }
  State& s = a.state_;
  s.joints.resize(numLinks);
  s.jointVelocity = VectorX::Zero(numDofs);
  for (int i = 0; i < numLinks; ++i) {
    ArticulatedLinkParams const& p = params.links[i];
    JointState& q = s.joints[i];
    Link const& l = a.links_[i];
    if (!p.initialPosition.empty()) {
      switch (l.joint) {
        case JointType::Revolute:
        case JointType::Prismatic: q.scalar = p.initialPosition[0]; break;
        case JointType::Spherical:
          q.rotation = Exp(Real3(p.initialPosition[0], p.initialPosition[1], p.initialPosition[2]));
          break;
        case JointType::Free:
          q.translation = Real3(p.initialPosition[0], p.initialPosition[1], p.initialPosition[2]);
          q.rotation = Exp(Real3(p.initialPosition[3], p.initialPosition[4], p.initialPosition[5]));
          break;
        case JointType::Fixed: break;
      }
    }
    for (std::size_t k = 0; k < p.initialVelocity.size(); ++k) s.jointVelocity[l.dofStart + k] = p.initialVelocity[k];
  }
  // scratch
  a.inertia_.resize(numLinks);
  a.stageStart_ = s.joints;
  a.saved_ = s.joints;
  a.jointTarget_ = VectorX::Zero(numDofs);
  a.kinematics_.motion.resize(6, numDofs);
  a.gradient_ = VectorX::Zero(numDofs);
  if (a.blockSolve_ == ArticulatedBlockSolve::Dense) a.SizeDenseBlock();
  a.composite_.resize(numLinks);
  a.own_.resize(numLinks);
  a.linkMetric_.resize(numLinks);
  a.jointBlocks_.resize(numLinks);
  a.localMotion_.resize(6, numDofs);
  a.shift_.resize(numLinks);
  a.treeSolver_.Reserve(numLinks);
  for (auto* v : {&a.wrenchForce_, &a.wrenchMoment_, &a.torqueSum_}) v->resize(numLinks);
  a.forceMoment_.resize(numLinks);
  // link poses and velocities from the joints: v_c = Σ (v_k + ω_k × c) q̇_k
  a.ComputeKinematics(s.joints, a.kinematics_);
  for (int i = 0; i < numLinks; ++i)
    if (!a.kinematics_.com[i].allFinite() || !a.kinematics_.linkRotation[i].coeffs().allFinite()) {
      error.Set(ErrorCode::InvalidArgument,
                "ArticulatedActorParams.links[" + std::to_string(i) +
                    "]: the link's initial pose overflows (centre of mass " + Format(a.kinematics_.com[i]) +
                    ") from the initialPosition and offsets of its joint and its ancestors' joints");
      return nullptr;
    }
  // (the spatial velocity (ω; v at the origin) summed down the tree: O(N))
  s.links.resize(numLinks);
  DynamicArray<Vector6> spatialVelocity(numLinks);
  for (int i = 0; i < numLinks; ++i) {
    int const parent = a.links_[i].parent;
    Vector6 const& velocity = spatialVelocity[i] =
        a.LinkVelocity(i, parent >= 0 ? spatialVelocity[parent] : Vector6::Zero());
    internal::RigidBodyMotion& m = s.links[i];
    m.position = a.kinematics_.com[i];
    m.rotation = a.kinematics_.linkRotation[i];
    m.angularVelocity = velocity.head<3>();
    m.linearVelocity = velocity.tail<3>() + velocity.head<3>().cross(m.position);
  }
  return actor;
}

void ArticulatedActor::PoseLink(int i, JointState const& q, Real3 const& parentPosition,
                                Quat const& parentRotation, LinkPose& pose) const {
  Link const& l = links_[i];
  Quat const pre = parentRotation * l.parentToJointRotation;
  Real3 origin = parentPosition + parentRotation * l.parentToJointPosition;
  Quat post = pre;
  switch (l.joint) {
    case JointType::Revolute: post = pre * Quat(Eigen::AngleAxis<real>(q.scalar, l.axis)); break;
    case JointType::Prismatic: origin += pre * (q.scalar * l.axis); break;
    case JointType::Spherical: post = pre * q.rotation; break;
    case JointType::Free:
      origin += pre * q.translation;
      post = pre * q.rotation;
      break;
    case JointType::Fixed: break;
  }
  post.normalize();
  pose.preRotation = pre;
  pose.postRotation = post;
  pose.jointOrigin = origin;
  pose.linkRotation = (post * l.jointToChildRotation).normalized();
  pose.linkPosition = origin + post * l.jointToChildPosition;
}

void ArticulatedActor::JointMotion(int i, Quat const& pre, Quat const& post, Real3 const& origin,
                                   Eigen::Ref<Eigen::Matrix<real, 6, Eigen::Dynamic>> motion) const {
  // each DoF's world motion (ω; v at the origin), v_O = o × ω for a rotation about o
  Link const& l = links_[i];
  auto rotationAbout = [&](int column, Real3 const& omega) { motion.col(column) << omega, origin.cross(omega); };
  auto translationAlong = [&](int column, Real3 const& direction) {
    motion.col(column) << Real3::Zero(), direction;
  };
  switch (l.joint) {
    case JointType::Revolute: rotationAbout(0, pre * l.axis); break;
    case JointType::Prismatic: translationAlong(0, pre * l.axis); break;
    case JointType::Spherical: {
      Real33 const postMatrix = post.toRotationMatrix();
      for (int a = 0; a < 3; ++a) rotationAbout(a, postMatrix.col(a));
      break;
    }
    case JointType::Free: {
      Real33 const preMatrix = pre.toRotationMatrix(), postMatrix = post.toRotationMatrix();
      for (int a = 0; a < 3; ++a) translationAlong(a, preMatrix.col(a));
      for (int a = 0; a < 3; ++a) rotationAbout(3 + a, postMatrix.col(a));
      break;
    }
    case JointType::Fixed: break;
  }
}

void ArticulatedActor::ComputeKinematics(DynamicArray<JointState> const& joints, Kinematics& k, bool withMotion) const {
  int const numLinks = GetNumLinks();
  for (auto* v : {&k.linkPosition, &k.com, &k.jointOrigin}) v->resize(numLinks);
  for (auto* v : {&k.linkRotation, &k.preRotation, &k.postRotation}) v->resize(numLinks);
  for (int i = 0; i < numLinks; ++i) {
    Link const& l = links_[i];
    LinkPose pose;
    PoseLink(i, joints[i], l.parent < 0 ? Real3::Zero() : k.linkPosition[l.parent],
             l.parent < 0 ? Quat::Identity() : k.linkRotation[l.parent], pose);
    k.preRotation[i] = pose.preRotation;
    k.postRotation[i] = pose.postRotation;
    k.jointOrigin[i] = pose.jointOrigin;
    k.linkRotation[i] = pose.linkRotation;
    k.linkPosition[i] = pose.linkPosition;
    k.com[i] = pose.linkPosition + pose.linkRotation * l.centerOfMass;
  }
  k.hasMotion = withMotion;
  if (withMotion) ComputeMotion(k);
}

void ArticulatedActor::ComputeMotion(Kinematics& k) const {
  k.motion.resize(6, numDofs_);
  for (int i = 0; i < GetNumLinks(); ++i)
    JointMotion(i, k.preRotation[i], k.postRotation[i], k.jointOrigin[i],
                k.motion.middleCols(links_[i].dofStart, links_[i].numDofs));
  k.hasMotion = true;
}

void ArticulatedActor::UpdateKinematics(bool withMotion) const {
  auto const same = [](JointState const& a, JointState const& b) {
    return a.scalar == b.scalar && a.translation == b.translation && a.rotation.coeffs() == b.rotation.coeffs();
  };
  if (std::equal(state_.joints.begin(), state_.joints.end(), kinematicsJoints_.begin(), kinematicsJoints_.end(),
                 same)) {
    if (withMotion && !kinematics_.hasMotion) ComputeMotion(kinematics_);
    return;
  }
  ComputeKinematics(state_.joints, kinematics_, withMotion);
  kinematicsJoints_ = state_.joints;
}

internal::LinkPath ArticulatedActor::GetLinkPath(int link) const {
  internal::LinkPath path;
  path.link = link;
  for (int i = link; i >= 0; i = links_[i].parent) path.links.push_back(i);
  std::reverse(path.links.begin(), path.links.end());
  for (int i : path.links) {
    Link const& l = links_[i];
    for (int a = 0; a < l.numDofs; ++a) {
      path.dofs.push_back(l.dofStart + a);
      path.dofLink.push_back(i);
      bool const rotates = l.joint == JointType::Revolute || l.joint == JointType::Spherical ||
                           (l.joint == JointType::Free && a >= 3);
      path.dofRotates.push_back(rotates ? 1 : 0);
    }
  }
  path.jacobian.setZero(6, static_cast<Eigen::Index>(path.dofs.size()));
  ComputeLinkFrame(path);
  return path;
}

void ArticulatedActor::ComputeLinkFrame(internal::LinkPath& path) const {
  // forward kinematics along the path only, each joint's world motion
  // (ω; v_O) written into its columns, then turned into (δt; δθ) of the link
  // frame: δt = v_O + ω × t
  Real3 position = Real3::Zero();
  Quat rotation = Quat::Identity();
  int column = 0;
  for (int i : path.links) {
    LinkPose pose;
    PoseLink(i, state_.joints[i], position, rotation, pose);
    JointMotion(i, pose.preRotation, pose.postRotation, pose.jointOrigin,
                path.jacobian.middleCols(column, links_[i].numDofs));
    column += links_[i].numDofs;
    position = pose.linkPosition;
    rotation = pose.linkRotation;
  }
  path.position = position;
  path.rotation = rotation;
  for (Eigen::Index c = 0; c < path.jacobian.cols(); ++c) {
    Real3 const omega = path.jacobian.col(c).head<3>();
    Real3 const velocity = path.jacobian.col(c).tail<3>() + omega.cross(position);
    path.jacobian.col(c) << velocity, omega;
  }
}

void ArticulatedActor::ComputeLinkFrameAlong(internal::LinkPath const& path, real const* d, real alpha,
                                             Real3& position, Quat& rotation) const {
  position = Real3::Zero();
  rotation = Quat::Identity();
  for (int i : path.links) {
    LinkPose pose;
    PoseLink(i, Advance(i, state_.joints[i], d + links_[i].dofStart, alpha), position, rotation, pose);
    position = pose.linkPosition;
    rotation = pose.linkRotation;
  }
}

real ArticulatedActor::LinkSpeedBound(internal::LinkPath const& path, real const* d, real alphaMax, real arm) const {
  // from the link towards the root: `reach` bounds the distance from the
  // current link's frame origin to the point; a joint's rotation turns the
  // point about its origin, jointToChildPosition farther, and its own
  // translation (prismatic, free) then lies between that origin and the parent's
  real speed = 0, reach = arm;
  for (auto it = path.links.rbegin(); it != path.links.rend(); ++it) {
    Link const& l = links_[*it];
    JointState const& q = state_.joints[*it];
    real const* x = d + l.dofStart;
    real const fromJoint = reach + l.jointToChildPosition.norm();
    real translation = 0;  // the farthest the joint's translation reaches
    switch (l.joint) {
      case JointType::Revolute: speed += std::abs(x[0]) * l.axis.norm() * fromJoint; break;
      case JointType::Prismatic:
        speed += std::abs(x[0]) * l.axis.norm();
        translation = (std::abs(q.scalar) + alphaMax * std::abs(x[0])) * l.axis.norm();
        break;
      case JointType::Spherical: speed += Real3(x[0], x[1], x[2]).norm() * fromJoint; break;
      case JointType::Free: {
        Real3 const dp(x[0], x[1], x[2]);
        speed += dp.norm() + Real3(x[3], x[4], x[5]).norm() * fromJoint;
        translation = q.translation.norm() + alphaMax * dp.norm();
        break;
      }
      case JointType::Fixed: break;
    }
    reach = fromJoint + translation + l.parentToJointPosition.norm();
  }
  return speed;
}

void ArticulatedActor::JointDifference(int link, JointState const& q, JointState const& q0, real* out) const {
  switch (links_[link].joint) {
    case JointType::Revolute:
    case JointType::Prismatic: out[0] = q.scalar - q0.scalar; break;
    case JointType::Spherical: {
      Real3 const d = Log(q0.rotation.conjugate() * q.rotation);
      for (int a = 0; a < 3; ++a) out[a] = d[a];
      break;
    }
    case JointType::Free: {
      Real3 const d = Log(q0.rotation.conjugate() * q.rotation);
      for (int a = 0; a < 3; ++a) {
        out[a] = q.translation[a] - q0.translation[a];
        out[3 + a] = d[a];
      }
      break;
    }
    case JointType::Fixed: break;
  }
}

Real3 ArticulatedActor::GetLinkPosition(int link) const {
  // from the committed pose, as GetLinkRotation (O(1); forward kinematics
  // of the whole tree per call made get_link_positions O(N²))
  internal::RigidBodyMotion const& m = state_.links[link];
  return m.position - m.rotation * links_[link].centerOfMass;
}

Quat ArticulatedActor::GetLinkRotation(int link) const { return state_.links[link].rotation; }

DynamicArray<real> ArticulatedActor::GetJointPositions() const {
  DynamicArray<real> positions(numDofs_, 0);
  JointState const rest;
  for (int i = 0; i < GetNumLinks(); ++i) JointDifference(i, state_.joints[i], rest, positions.data() + links_[i].dofStart);
  return positions;
}

DynamicArray<real> ArticulatedActor::GetJointVelocities() const {
  return DynamicArray<real>(state_.jointVelocity.data(), state_.jointVelocity.data() + numDofs_);
}

real ArticulatedActor::GetKineticEnergy() const {
  real energy = 0;
  for (int i = 0; i < GetNumLinks(); ++i) {
    internal::RigidBodyMotion const& m = state_.links[i];
    Real3 const bodyOmega = m.rotation.conjugate() * m.angularVelocity;
    energy += 0.5 * links_[i].mass * m.linearVelocity.squaredNorm() +
              0.5 * bodyOmega.dot(links_[i].inertia.asDiagonal() * bodyOmega);
  }
  for (int i = 0; i < GetNumLinks(); ++i)
    for (int k = links_[i].dofStart; k < links_[i].dofStart + links_[i].numDofs; ++k)
      energy += 0.5 * links_[i].armature * state_.jointVelocity[k] * state_.jointVelocity[k];
  return energy;
}

Real3 ArticulatedActor::GetLinearMomentum() const {
  Real3 p = Real3::Zero();
  for (int i = 0; i < GetNumLinks(); ++i) p += links_[i].mass * state_.links[i].linearVelocity;
  return p;
}

Real3 ArticulatedActor::GetAngularMomentum() const {
  Real3 l = Real3::Zero();
  for (int i = 0; i < GetNumLinks(); ++i) {
    internal::RigidBodyMotion const& m = state_.links[i];
    l += m.position.cross(links_[i].mass * m.linearVelocity) +
         m.rotation * (links_[i].inertia.asDiagonal() * (m.rotation.conjugate() * m.angularVelocity));
  }
  return l;
}

void ArticulatedActor::ComputeCompositeInertias() const {
  UpdateKinematics();
  int const numLinks = GetNumLinks();
  for (int i = 0; i < numLinks; ++i) {
    Real33 const r = kinematics_.linkRotation[i].toRotationMatrix();
    composite_[i] = SpatialStiffness(r * links_[i].inertia.asDiagonal() * r.transpose(), links_[i].mass,
                                     kinematics_.com[i]);
  }
  for (int i = numLinks - 1; i > 0; --i)
    if (links_[i].parent >= 0) composite_[links_[i].parent] += composite_[i];
}

MatrixX ArticulatedActor::ComputeMassMatrix() const {
  // CRBA: composite spatial inertias about the world origin, summed from the
  // leaves; M_jk = s_jᵀ I_c(k) s_k for j on the path from k to the root
  ComputeCompositeInertias();
  int const numLinks = GetNumLinks();
  MatrixX mass = MatrixX::Zero(numDofs_, numDofs_);
  for (int k = 0; k < numLinks; ++k) {
    Link const& lk = links_[k];
    if (lk.numDofs == 0) continue;
    Eigen::Matrix<real, 6, Eigen::Dynamic> const force = composite_[k] * kinematics_.motion.middleCols(lk.dofStart, lk.numDofs);
    for (int j = k; j >= 0; j = links_[j].parent) {
      Link const& lj = links_[j];
      if (lj.numDofs == 0) continue;
      MatrixX const block = kinematics_.motion.middleCols(lj.dofStart, lj.numDofs).transpose() * force;
      mass.block(lj.dofStart, lk.dofStart, lj.numDofs, lk.numDofs) = block;
      mass.block(lk.dofStart, lj.dofStart, lk.numDofs, lj.numDofs) = block.transpose();
    }
  }
  for (int i = 0; i < numLinks; ++i)
    for (int k = links_[i].dofStart; k < links_[i].dofStart + links_[i].numDofs; ++k) mass(k, k) += links_[i].armature;
  return mass;
}

Vector6 ArticulatedActor::LinkVelocity(int i, Vector6 const& parentVelocity) const {
  Link const& l = links_[i];
  Vector6 velocity = parentVelocity;
  for (int k = l.dofStart; k < l.dofStart + l.numDofs; ++k)
    velocity += kinematics_.motion.col(k) * state_.jointVelocity[k];
  return velocity;
}

VectorX ArticulatedActor::ComputeBiasForces(Real3 const& gravity) const {
  // RNEA in world coordinates at the origin, q̈ = 0: V_i = V_p + S q̇,
  // A_i = A_p + Ṡ q̇ with Ṡ = V ×ₘ S (V the velocity of the frame the axis
  // is fixed in: the parent's for revolute, prismatic and free-translation
  // axes, the link's for spherical and free-rotation axes), A_root = −g
  // (gravity as a base acceleration); F_i = I_i A_i + V_i ×_f I_i V_i;
  // τ_k = S_kᵀ Σ_subtree F.
  UpdateKinematics();
  int const numLinks = GetNumLinks();
  auto crossMotion = [](Vector6 const& v, Vector6 const& m) {
    Vector6 r;
    r << v.head<3>().cross(m.head<3>()), v.head<3>().cross(m.tail<3>()) + v.tail<3>().cross(m.head<3>());
    return r;
  };
  auto crossForce = [](Vector6 const& v, Vector6 const& f) {
    Vector6 r;
    r << v.head<3>().cross(f.head<3>()) + v.tail<3>().cross(f.tail<3>()), v.head<3>().cross(f.tail<3>());
    return r;
  };
  DynamicArray<Vector6> velocity(numLinks), acceleration(numLinks), force(numLinks);
  Vector6 baseAcceleration;
  baseAcceleration << Real3::Zero(), -gravity;
  for (int i = 0; i < numLinks; ++i) {
    Link const& l = links_[i];
    Vector6 const parentVelocity = l.parent < 0 ? Vector6::Zero() : velocity[l.parent];
    Vector6 const parentAcceleration = l.parent < 0 ? baseAcceleration : acceleration[l.parent];
    Vector6 const v = LinkVelocity(i, parentVelocity);
    Vector6 a = parentAcceleration;
    for (int k = l.dofStart; k < l.dofStart + l.numDofs; ++k) {
      bool const fixedInChild = l.joint == JointType::Spherical ||
                                (l.joint == JointType::Free && k >= l.dofStart + 3);
      a += crossMotion(fixedInChild ? v : parentVelocity, kinematics_.motion.col(k)) * state_.jointVelocity[k];
    }
    velocity[i] = v;
    acceleration[i] = a;
    Real33 const r = kinematics_.linkRotation[i].toRotationMatrix();
    Matrix6 const inertia =
        SpatialStiffness(r * l.inertia.asDiagonal() * r.transpose(), l.mass, kinematics_.com[i]);
    force[i] = inertia * a + crossForce(v, inertia * v);
  }
  for (int i = numLinks - 1; i > 0; --i) force[links_[i].parent] += force[i];
  VectorX bias(numDofs_);
  for (int i = 0; i < numLinks; ++i)
    for (int k = links_[i].dofStart; k < links_[i].dofStart + links_[i].numDofs; ++k)
      bias[k] = kinematics_.motion.col(k).dot(force[i]);
  return bias;
}

// ---- stage interface ----

void ArticulatedActor::AppendDofBlockSizes(DynamicArray<int>& sizes) const {
  for (Link const& l : links_)
    if (l.numDofs > 0) sizes.push_back(l.numDofs);
}

void ArticulatedActor::WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const {
  // only a floating base moves rigidly: its free joint's translation (in the
  // joint frame) and a rotation ω about the world origin (local increment
  // R_postᵀ ω, the joint origin o moving by ω × o)
  if (!IsFloatingBase()) return;
  UpdateKinematics();
  Real33 const pre = kinematics_.preRotation[0].toRotationMatrix();
  Real33 const post = kinematics_.postRotation[0].toRotationMatrix();
  auto block = modes.middleRows(dofOffset_, numDofs_);
  block.setZero();
  block.topLeftCorner<3, 3>() = pre.transpose();
  block.block<3, 3>(0, 3) = -pre.transpose() * Hat(kinematics_.jointOrigin[0]);
  block.block<3, 3>(3, 3) = post.transpose();
}

void ArticulatedActor::WriteDofInverseMasses(Span<real> inverseMasses) const {
  // the diagonal of the CRBA mass matrix, M_jj = s_jᵀ I_c(k) s_j + armature
  // for DoF j of link k (I_c(k) the composite inertia of k's subtree), in the
  // kinematics and composite scratch: no allocation
  ComputeCompositeInertias();
  int const numLinks = GetNumLinks();
  for (int k = 0; k < numLinks; ++k)
    for (int j = links_[k].dofStart; j < links_[k].dofStart + links_[k].numDofs; ++j) {
      auto const s = kinematics_.motion.col(j);
      inverseMasses[dofOffset_ + j] = 1 / (s.dot(composite_[k] * s) + links_[k].armature);
    }
}

void ArticulatedActor::AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const {
  if (IsActive()) {
    // one block per joint with DoFs (its diagonal block)
    for (Link const& l : links_) {
      if (l.numDofs == 0) continue;
      DynamicArray<int> dofs(l.numDofs);
      for (int k = 0; k < l.numDofs; ++k) dofs[k] = dofOffset_ + l.dofStart + k;
      dofLists.push_back(std::move(dofs));
    }
    // and one over the DoFs of the bodies its links are coupled with
    if (!couplingDofs_.empty()) dofLists.push_back(couplingDofs_);
    return;
  }
  // one dense block over all the actor's DoFs
  DynamicArray<int> dofs(numDofs_);
  for (int k = 0; k < numDofs_; ++k) dofs[k] = dofOffset_ + k;
  dofLists.push_back(std::move(dofs));
}

void ArticulatedActor::BeginStage(internal::StageContext const& context) {
  internal::StageCoefficients const& requested = context.coefficients;
  Real3 const& gravity = context.gravity;
  stage_ = requested.ForBody(state_.hasHistory);
  gravity_ = gravity;
  for (int i = 0; i < GetNumLinks(); ++i)
    inertia_[i].Begin(stage_, links_[i].mass, links_[i].inertia, state_.links[i]);
  stageStart_ = state_.joints;
  // the reduced prediction Δ̂q = c Δₚ + β h (a q̇ⁿ + b q̇ⁿ⁻¹) (the armature's
  // target, and Newton's first iterate)
  real const betaH = stage_.beta * stage_.duration;
  jointTarget_ = betaH * stage_.aVelocity * state_.jointVelocity;
  if (stage_.usesHistory) {
    jointTarget_ += betaH * stage_.bVelocity * state_.previousJointVelocity;
    for (int i = 0; i < GetNumLinks(); ++i) {
      real previous[6];
      JointDifference(i, state_.previousJoints[i], state_.joints[i], previous);
      for (int a = 0; a < links_[i].numDofs; ++a) jointTarget_[links_[i].dofStart + a] += stage_.cPrevious * previous[a];
    }
  }
  saved_ = state_.joints;
  // Newton's first iterate: the prediction, or, with a history, the joint
  // velocity extrapolated at the last step's acceleration,
  // v* = vⁿ + (h/hₚ)(vⁿ − vⁿ⁻¹), placed as the stage's update places a
  // velocity: Δ = c Δₚ + β h v* (the minimizer does not depend on it). Only
  // where h/hₚ <= kMaxExtrapolationRatio: after a much shorter step (1e-15 s)
  // vⁿ − vⁿ⁻¹ is round-off of the positions divided by hₚ, not an
  // acceleration, and h/hₚ would carry it to a first iterate Newton cannot
  // come back from; the prediction is the first iterate then
  firstIterate_ = jointTarget_;
  real const r = state_.lastStageDuration > 0 ? stage_.duration / state_.lastStageDuration : 0;
  if (extrapolateFirstIterate_ && state_.hasHistory && r > 0 && r <= kMaxExtrapolationRatio) {
    firstIterate_ += betaH * ((1 - stage_.aVelocity + r) * state_.jointVelocity -
                              (stage_.bVelocity + r) * state_.previousJointVelocity);
  }
}

void ArticulatedActor::MoveToFirstIterate() { ApplyLocalIncrement(firstIterate_.data(), 1); }

real ArticulatedActor::Energy(internal::OwnedContributors owned) const {
  energyRoundOffScale_ = 0;
  if (!owned(0)) return 0;  // its one dense contributor
  UpdateKinematics(false);
  // the links' terms cancel (gravity against inertia) and are differences
  // of poses: their round-off scale (Actor::EnergyRoundOffScale)
  real energy = 0, scale = 0;
  for (int i = 0; i < GetNumLinks(); ++i) {
    real inertiaScale = 0;
    real const inertia = inertia_[i].Energy(kinematics_.com[i], kinematics_.linkRotation[i], &inertiaScale);
    real const gravity = links_[i].mass * gravity_.dot(kinematics_.com[i]);
    energy += inertia - gravity;
    scale += inertia + inertiaScale + std::abs(gravity);
  }
  energyRoundOffScale_ = scale;
  // joint-space terms: ½ w a (Δq − Δ̂q)² + d/(2h) Δq²
  real const weight = stage_.InertiaWeight(), h = stage_.duration;
  for (int i = 0; i < GetNumLinks(); ++i) {
    Link const& l = links_[i];
    if (l.numDofs == 0 || (l.armature == 0 && l.damping == 0)) continue;
    real d[6];
    JointDifference(i, state_.joints[i], stageStart_[i], d);
    for (int a = 0; a < l.numDofs; ++a) {
      real const r = d[a] - jointTarget_[l.dofStart + a];
      energy += 0.5 * weight * l.armature * r * r + 0.5 * l.damping / h * d[a] * d[a];
    }
  }
  return energy;
}

void ArticulatedActor::ComputeGradientAndTreeTerms(internal::HessianAssembler const& assembler,
                                                   bool projectHessian) const {
  using internal::ArticulatedTreeSolver;
  UpdateKinematics();
  Kinematics const& k = kinematics_;
  int const numLinks = GetNumLinks();
  // every spatial quantity of link i about its joint origin o_i (a local
  // point: about the world origin the products of a long chain cancel
  // digits); the DoFs' motion about it: rotations (ω; 0), translations (0; d)
  for (int i = 0; i < numLinks; ++i) {
    Link const& l = links_[i];
    shift_[i] = l.parent >= 0 ? Real3(k.jointOrigin[i] - k.jointOrigin[l.parent]) : Real3::Zero();
    for (int c = l.dofStart; c < l.dofStart + l.numDofs; ++c) {
      bool const rotation = !k.motion.col(c).head<3>().isZero();
      localMotion_.col(c).head<3>() = k.motion.col(c).head<3>();
      localMotion_.col(c).tail<3>() = rotation ? Real3::Zero() : Real3(k.motion.col(c).tail<3>());
    }
  }
  // link wrenches: f at the centre of mass (inertia residual − m g), τ a
  // pure torque; subtree sums of f, of the moment Σ (τ + (c − o) × f), of τ,
  // of (c − o) fᵀ, and of Y = spatial stiffness + curvature, each about the
  // subtree root's joint origin o (shifted on the way up)
  // (each link's own terms on the assembler's threads: they are independent)
  assembler.ParallelFor(numLinks, internal::kElementGrain, [&](int begin, int end, int) {
    for (int i = begin; i < end; ++i) {
      Real3 f, tau;
      Real33 rotation;
      inertia_[i].Derivatives(k.com[i], k.linkRotation[i], f, tau, &rotation);
      f -= links_[i].mass * gravity_;
      Real3 const arm = k.com[i] - k.jointOrigin[i];
      wrenchForce_[i] = f;
      wrenchMoment_[i] = tau + arm.cross(f);
      torqueSum_[i] = tau;
      forceMoment_[i] = arm * f.transpose();
      own_[i] =
          SpatialStiffness(rotation, inertia_[i].TranslationStiffness(), arm) + Curvature(forceMoment_[i], f, tau);
    }
  });
  // the composites Y only for the dense block (the tree solver forms its own)
  bool const dense = !IsActive();
  if (dense)
    for (int i = 0; i < numLinks; ++i) composite_[i] = own_[i];
  for (int i = numLinks - 1; i > 0; --i) {
    int const p = links_[i].parent;
    Real3 const& r = shift_[i];
    wrenchForce_[p] += wrenchForce_[i];
    wrenchMoment_[p] += wrenchMoment_[i] + r.cross(wrenchForce_[i]);
    torqueSum_[p] += torqueSum_[i];
    forceMoment_[p] += forceMoment_[i] + r * wrenchForce_[i].transpose();
    if (dense) composite_[p] += ArticulatedTreeSolver::ShiftToParent(r, composite_[i]);
  }
  // gradient: g_k = ω_k·M_sub + v_k·F_sub (the backward pass of RNEA)
  gradient_.setZero();
  real* out = gradient_.data();
  for (int i = 0; i < numLinks; ++i)
    for (int c = links_[i].dofStart; c < links_[i].dofStart + links_[i].numDofs; ++c)
      out[c] += localMotion_.col(c).head<3>().dot(wrenchMoment_[i]) +
                localMotion_.col(c).tail<3>().dot(wrenchForce_[i]);
  // single-body constraints on links folded into the tree: a wrench and a
  // stiffness at the link, as the links' inertia terms
  if (!couplingDofs_.empty()) {
    couplingGradient_.setZero();
    couplingHessian_.setZero();
    for (CoupledLink& coupled : coupledLinks_) {
      coupled.coupling.setZero();
      coupled.stiffness.setZero();
    }
  }
  if (!folded_.empty()) foldedDiagonal_.setZero();
  for (FoldedConstraint const& folded : folded_) AddFoldedConstraint(folded, projectHessian);
  for (CoupledLink& coupled : coupledLinks_) coupled.ownWithout = own_[coupled.link];

  // each joint's extra block E_c = H_cc − sym(S_cᵀ Y_c S_c) (the tree
  // solver's jointExtras): H_cc is the composite-rigid-body part S_cᵀ K S_c
  // plus the curvature within the joint, so E_c is that curvature less
  // sym(S_cᵀ C S_c), C the curvature in Y. For DoF a upstream of DoF b (x
  // moved by Exp(a) Exp(b)), ∂²x/∂a∂b = ω_a × u_b(x) and
  // ∂²ω/∂a∂b = ½ ω_a × ω_b, summed over b's subtree, give
  // H_ab += ω_a·(P ω_b − ω_b tr P + v_b × F) + ½ ω_a·(ω_b × T) between
  // joints (the Curvature operator); within one spherical or free joint the
  // rotations are exponential coordinates: the symmetric ½(ÂB̂ + B̂Â) and no
  // torque term; a free joint's translations act before its rotations.
  // With q_b = P ω_b − ω_b tr P + v_b × F, the curvature within the joint
  // is ½(ω_a·q_b + ω_b·q_a) for a rotation a (ω_b·q_b on the diagonal) and
  // nothing for a translation a before it, while sym(S_cᵀ C S_c)_ab =
  // ½(ω_a·(q_b − ½ τ × ω_b) + ω_b·(q_a − ½ τ × ω_a)), whose torque terms
  // cancel: E_c is zero but for a free joint's translation a and rotation b,
  // −½ ω_b·(v_a × F)
  for (int c = 0; c < numLinks; ++c) {
    Link const& lk = links_[c];
    jointBlocks_[c].topLeftCorner(lk.numDofs, lk.numDofs).setZero();
    if (lk.joint != JointType::Free) continue;
    for (int a = 0; a < 3; ++a) {
      Real3 const va = localMotion_.col(lk.dofStart + a).tail<3>();
      Real3 const moment = va.cross(wrenchForce_[c]);
      for (int b = 3; b < 6; ++b) {
        real const value = -0.5 * localMotion_.col(lk.dofStart + b).head<3>().dot(moment);
        jointBlocks_[c](a, b) = value;
        jointBlocks_[c](b, a) = value;
      }
    }
  }
  // joint-space terms (armature, damping); rotations through J_r⁻¹ (Gauss–Newton)
  real const weight = stage_.InertiaWeight(), h = stage_.duration;
  for (int i = 0; i < numLinks; ++i) {
    Link const& l = links_[i];
    if (l.numDofs == 0 || (l.armature == 0 && l.damping == 0)) continue;
    real d[6];
    JointDifference(i, state_.joints[i], stageStart_[i], d);
    real const stiffness = weight * l.armature + l.damping / h;
    Matrix6& block = jointBlocks_[i];
    auto addRotation = [&](int first) {
      Real3 const phi(d[first], d[first + 1], d[first + 2]);
      Real33 const dPhi = RightJacobianInverse(phi);
      Real3 residual;
      for (int a = 0; a < 3; ++a)
        residual[a] = weight * l.armature * (d[first + a] - jointTarget_[l.dofStart + first + a]) +
                      l.damping / h * d[first + a];
      Real3 const g = dPhi.transpose() * residual;
      for (int a = 0; a < 3; ++a) out[l.dofStart + first + a] += g[a];
      block.block<3, 3>(first, first) += stiffness * dPhi.transpose() * dPhi;
    };
    auto addLinear = [&](int a) {
      out[l.dofStart + a] += weight * l.armature * (d[a] - jointTarget_[l.dofStart + a]) + l.damping / h * d[a];
      block(a, a) += stiffness;
    };
    switch (l.joint) {
      case JointType::Revolute:
      case JointType::Prismatic: addLinear(0); break;
      case JointType::Spherical: addRotation(0); break;
      case JointType::Free:
        for (int a = 0; a < 3; ++a) addLinear(a);
        addRotation(3);
        break;
      case JointType::Fixed: break;
    }
  }
  // the folded constraints' projected link-frame curvature (a diagonal)
  if (!folded_.empty())
    for (int i = 0; i < numLinks; ++i)
      for (int a = 0; a < links_[i].numDofs; ++a) jointBlocks_[i](a, a) += foldedDiagonal_[links_[i].dofStart + a];
}

void ArticulatedActor::AddGradientAndHessian(internal::HessianAssembler& assembler, int firstContributor,
                                         internal::AssemblyOptions const& options) const {
  bool const projectHessian = options.projectHessian;
  if (!assembler.Evaluates(firstContributor)) return;
  ComputeGradientAndTreeTerms(assembler, projectHessian);
  int const numLinks = GetNumLinks();
  if (IsActive()) {
    // one contributor per joint: its gradient and diagonal block; the rest of
    // the Hessian stays in own_ for FactorizeOwnBlock
    int contributor = firstContributor;
    for (int i = 0; i < numLinks; ++i) {
      int const m = links_[i].numDofs;
      if (m == 0) continue;
      assembler.AddGradient(contributor, gradient_.segment(links_[i].dofStart, m));
      assembler.AddBlock(contributor, jointBlocks_[i].topLeftCorner(m, m));
      ++contributor;
    }
    // the couplings' terms on the other bodies' DoFs (the Schur complement's
    // term joins them after the tree's factorization)
    if (!couplingDofs_.empty()) {
      assembler.AddGradient(contributor, couplingGradient_);
      assembler.AddBlock(contributor, couplingHessian_);
    }
    return;
  }
  // the dense block: H_cc = sym(S_cᵀ Y_c S_c) + E_c, and H_jc = S_jᵀ Y_c S_c
  // for j a strict ancestor of c, S_j carried to o_c (v ← v − (o_c − o_j) × ω)
  Kinematics const& k = kinematics_;
  SizeDenseBlock();  // (once: Tree actors size it only where the scene falls back to the dense block)
  hessian_.setZero();
  for (int c = 0; c < numLinks; ++c) {
    Link const& lk = links_[c];
    int const m = lk.numDofs;
    if (m == 0) continue;
    SpatialColumns const s = localMotion_.middleCols(lk.dofStart, m);  // fixed capacity: no allocation
    SpatialColumns force;
    force.noalias() = composite_[c] * s;
    auto diagonal = hessian_.block(lk.dofStart, lk.dofStart, m, m);
    diagonal.noalias() = 0.5 * s.transpose() * force;
    diagonal.noalias() += 0.5 * force.transpose() * s;
    diagonal += jointBlocks_[c].topLeftCorner(m, m);
    for (int j = lk.parent; j >= 0; j = links_[j].parent) {
      Link const& lj = links_[j];
      if (lj.numDofs == 0) continue;
      SpatialColumns ancestor = localMotion_.middleCols(lj.dofStart, lj.numDofs);
      Real3 const r = k.jointOrigin[c] - k.jointOrigin[j];
      for (int a = 0; a < lj.numDofs; ++a)
        ancestor.col(a).tail<3>() -= r.cross(Real3(ancestor.col(a).head<3>()));
      hessian_.block(lj.dofStart, lk.dofStart, lj.numDofs, m).noalias() = ancestor.transpose() * force;
      hessian_.block(lk.dofStart, lj.dofStart, m, lj.numDofs) =
          hessian_.block(lj.dofStart, lk.dofStart, lj.numDofs, m).transpose();
    }
  }
  if (projectHessian) ModifyHessianToPositiveDefinite();
  assembler.AddGradient(firstContributor, gradient_);
  assembler.AddBlock(firstContributor, hessian_);
}

void ArticulatedActor::SizeDenseBlock() const {
  if (hessian_.rows() == numDofs_) return;
  // 3N × 3N, with the modified Cholesky's factor: 0.14 GB at N = 1,000,
  // 3.6 GB at N = 5,000, which the tree solve never needs
  hessian_ = MatrixX::Zero(numDofs_, numDofs_);
  // sized by a factorization (assigning LDLT(n) copies its uninitialized
  // status flag: undefined behaviour, UBSan)
  modifiedFactor_.compute(MatrixX::Identity(numDofs_, numDofs_));
  modifiedColumn_ = VectorX::Zero(numDofs_);
  modifiedOrder_.assign(numDofs_, 0);
}

void ArticulatedActor::ClearFolded() {
  folded_.clear();
  coupledLinks_.clear();
  couplingDofs_.clear();
  numCoupled_ = 0;
}

bool ArticulatedActor::Fold(internal::LinkTerm& term) {
  if (!IsActive() || term.GetLinkOwner() != &GetStageDofs()) return false;
  if (foldedDiagonal_.size() != numDofs_) foldedDiagonal_.setZero(numDofs_);
  FoldedConstraint folded;
  folded.term = &term;
  if (!term.GetOtherDofs().empty()) {
    // the other body's DoFs join the coupling block (in order of first use)
    for (int dof : term.GetOtherDofs()) {
      auto const found = std::find(couplingDofs_.begin(), couplingDofs_.end(), dof);
      folded.couplingIndex.push_back(static_cast<int>(found - couplingDofs_.begin()));
      if (found == couplingDofs_.end()) couplingDofs_.push_back(dof);
    }
    int const link = term.GetLinkPath().link;
    auto const coupled = std::find_if(coupledLinks_.begin(), coupledLinks_.end(),
                                      [&](CoupledLink const& c) { return c.link == link; });
    folded.coupledLink = static_cast<int>(coupled - coupledLinks_.begin());
    if (coupled == coupledLinks_.end()) {
      CoupledLink added;
      added.link = link;
      added.dofs = term.GetLinkPath().dofs;
      added.jacobian.setZero(6, static_cast<Eigen::Index>(added.dofs.size()));
      coupledLinks_.push_back(std::move(added));
    }
    ++numCoupled_;
    int const n = static_cast<int>(couplingDofs_.size());
    for (CoupledLink& c : coupledLinks_) c.coupling.setZero(6, n);
    couplingGradient_.setZero(n);
    couplingHessian_.setZero(n, n);
    schurTerm_.setZero(n, n);
    schurColumns_.setZero(n, 6);
    treeRhs_.setZero(numDofs_);
    treeSolution_.setZero(numDofs_);
    pivotChanges_.assign(links_.size(), Matrix6::Zero());
  }
  folded_.push_back(std::move(folded));
  foldedMaxDimension_ = std::max(foldedMaxDimension_, term.GetDimension());
  foldedMaxDofs_ = std::max(foldedMaxDofs_, term.GetNumDofs());
  foldedWorkspace_.Reserve(foldedMaxDimension_, foldedMaxDofs_);
  return true;
}

void ArticulatedActor::AddFoldedConstraint(FoldedConstraint const& folded, bool projectHessian) const {
  internal::TermWorkspace::FoldedBlock hessian;
  Vector6 wrench;
  bool exactCurvature = false;
  internal::TermWorkspace& ws = foldedWorkspace_;
  internal::LinkTerm const& term = *folded.term;
  if (!term.AddLinkTerms(projectHessian, ws, hessian, wrench, exactCurvature)) return;
  // the gradient Jᵀ f (ws.r, over the term's DoF list) on the path's DoFs
  // and the other body's
  Span<int const> const dofs = term.GetPathDofs();
  Span<int const> const pathColumns = term.GetPathColumns();
  int const numPath = static_cast<int>(dofs.size());
  int const numOther = static_cast<int>(folded.couplingIndex.size());
  for (int j = 0; j < numPath; ++j) gradient_[dofs[j] - dofOffset_] += ws.r[pathColumns[j]];
  internal::LinkPath const& path = term.GetLinkPath();
  int const link = path.link;
  if (numOther > 0) {
    // the coupling: H_lo into the link's W (and the link frame's Jacobian
    // at this iterate, for the complement), H_oo over the other DoFs
    CoupledLink& coupled = coupledLinks_[folded.coupledLink];
    coupled.jacobian = path.jacobian;
    Span<int const> const otherColumns = term.GetOtherColumns();
    for (int j = 0; j < numOther; ++j) {
      int const cj = folded.couplingIndex[j];
      couplingGradient_[cj] += ws.r[otherColumns[j]];
      coupled.coupling.col(cj) += hessian.block<6, 1>(0, 6 + j);
      for (int i = 0; i < numOther; ++i) couplingHessian_(folded.couplingIndex[i], cj) += hessian(6 + i, 6 + j);
    }
  }
  // the stiffness about o_L: the link frame's increments (δt; δθ) of the
  // tree's motion (ω; v at o_L) are T (ω; v), T = [[−[r]×, I], [I, 0]],
  // r = t − o_L
  Real3 const r = kinematics_.linkPosition[link] - kinematics_.jointOrigin[link];
  Matrix6 t = Matrix6::Zero();
  t.topLeftCorner<3, 3>() = -Hat(r);
  t.topRightCorner<3, 3>().setIdentity();
  t.bottomLeftCorner<3, 3>().setIdentity();
  Matrix6& stiffness = numOther > 0 ? coupledLinks_[folded.coupledLink].stiffness : own_[link];
  stiffness.noalias() += t.transpose() * hessian.topLeftCorner<6, 6>() * t;
  if (wrench.isZero()) return;
  Real3 const force = wrench.head<3>(), moment = wrench.tail<3>();
  if (!exactCurvature) {
    // projected (or the diagonal geometric stiffness): a coupling's frame
    // curvature K by its column norms over the path's DoFs, a diagonal the
    // joints' blocks take (as the scene's matrix takes them on the dense
    // block, with G's), O(path²). Without it, a chain holding a hanging tet
    // block by a node took Newton steps of hundreds of radians (the large
    // inertia residuals K balances stay in the tree's curvature) and
    // stalled; a single-body constraint converges as well without it, and
    // its diagonal slowed the last iterations to linear convergence
    if (numOther == 0) return;
    for (int j = 0; j < numPath; ++j) {
      real squares = 0;
      for (int i = 0; i < numPath; ++i) {
        real const value = i <= j ? path.Curvature(i, j, force, moment) : path.Curvature(j, i, force, moment);
        squares += value * value;
      }
      foldedDiagonal_[path.dofs[j]] += std::sqrt(squares);
    }
    return;
  }
  // the link frame's own curvature against the wrench (F at t, pure moment
  // M): own_ as the links' inertia wrenches, and the subtree sums the
  // joints' blocks E_c read, along the path
  own_[link] += Curvature(r * force.transpose(), force, moment);
  for (int j = link; j >= 0; j = links_[j].parent) {
    forceMoment_[j] += (kinematics_.linkPosition[link] - kinematics_.jointOrigin[j]) * force.transpose();
    wrenchForce_[j] += force;
    torqueSum_[j] += moment;
  }
}

internal::ArticulatedTreeSolver::System ArticulatedActor::TreeSystem() const {
  return {linkParent_, linkDofStart_, linkNumDofs_, localMotion_, own_, jointBlocks_, shift_, linkMetric_};
}

bool ArticulatedActor::Factorize(internal::HessianAssembler& assembler, int firstContributor,
                                         bool projectHessian, bool separateCouplings, std::string& reason) {
  // the joints' assembled diagonal blocks (the joint constraints' terms
  // included) replace the actor's own; the scene's matrix gets the identity
  int contributor = firstContributor;
  for (int i = 0; i < GetNumLinks(); ++i) {
    int const m = links_[i].numDofs;
    if (m == 0) continue;
    auto block = jointBlocks_[i].topLeftCorner(m, m);
    assembler.ReadBlock(contributor, block);
    assembler.WriteBlock(contributor, Matrix6::Identity().topLeftCorner(m, m));
    ++contributor;
  }
  JoinCouplingStiffness(true);
  int failedLink = -1;
  bool factorized = !projectHessian && treeSolver_.Factorize(TreeSystem(), false, &failedLink);
  // coupled with other bodies, an indefinite block is left to the stage
  // solver's projected retry (the couplings' terms projected too, as on the
  // dense block): modifying it with the couplings' exact terms in it took
  // Newton tens of iterations per step where the retry takes four
  if (!factorized && !projectHessian && !couplingDofs_.empty()) return false;
  if (!factorized) {
    // Not positive definite (or the scene projects every Hessian): the tree
    // made positive definite at once, as the projected retry would, without
    // re-assembling the scene for it (the actor's block is solved apart from
    // the scene's matrix, so its projection is its own; the retry cost the
    // falling chain ~2 extra assemblies per step). The metric that bounds the
    // modification: each link's inertia w·M about its joint origin
    assembler.ParallelFor(GetNumLinks(), internal::kElementGrain, [&](int begin, int end, int) {
      for (int i = begin; i < end; ++i) {
        Real33 const r = kinematics_.linkRotation[i].toRotationMatrix();
        real const w = inertia_[i].Weight();
        linkMetric_[i] = SpatialStiffness(w * r * links_[i].inertia.asDiagonal() * r.transpose(),
                                          w * links_[i].mass, kinematics_.com[i] - kinematics_.jointOrigin[i]);
      }
    });
    ++modifiedTreeFactorizations_;
    if (couplingDofs_.empty() || !separateCouplings) {
      // from the joint where the exact attempt failed (the joints before it
      // stay as they were eliminated)
      factorized = projectHessian ? treeSolver_.Factorize(TreeSystem(), true, &failedLink)
                                  : treeSolver_.ContinueModified(TreeSystem(), &failedLink);
    } else {
      // Coupled with other bodies, the modification kept apart from the
      // couplings (the stage solver's last resort, after the modified sum
      // left an indefinite Schur complement: where the couplings'
      // stiffness hides an indefinite actor block, the complement takes the
      // stiffness out again): the modification is the actor's own, made
      // without the couplings' stiffness (A₊ = A + blockdiag(ΔD), the
      // changes kept in the joints' E_i), and the stiffness then joins A₊.
      // With projected couplings (PSD over the link frame and the other
      // body) the scene's matrix is then positive definite, and so is the
      // complement. (Not the first choice: with large inertia residuals the
      // actor's block alone is far from definite, and its modification a
      // poorer model than the sum's; Newton took hundreds of iterations on
      // a chain holding a hanging tet block)
      JoinCouplingStiffness(false);
      factorized = treeSolver_.Factorize(TreeSystem(), true, &failedLink, pivotChanges_);
      JoinCouplingStiffness(true);
      if (factorized) {
        for (int i = 0; i < GetNumLinks(); ++i) jointBlocks_[i] += pivotChanges_[i];
        factorized = treeSolver_.Factorize(TreeSystem(), false, &failedLink) ||
                     treeSolver_.Factorize(TreeSystem(), true, &failedLink);
      }
    }
  }
  if (!factorized) {
    // Last resort: the Gauss–Newton Hessian, each link's inertia metric w·M
    // (linkMetric_) for its own block and each joint's extra block projected
    // onto its PSD part: positive definite, so its step descends. The
    // modified factorization can fail where a modified pivot's Schur
    // complement leaves directions the joint does not eliminate (a spherical
    // joint's translations) to grow up the chain: a 500-link falling chain
    // at dt = 1/60 grew its pivots by ~3 % per joint after the first
    // modification, from 1e9 to 1e17, where round-off made the last one fail
    // (docs/articulated.md, "Indefinite iterates")
    for (int i = 0; i < GetNumLinks(); ++i) {
      own_[i] = linkMetric_[i];
      int const m = links_[i].numDofs;
      if (m == 0) continue;
      auto const extra = ComputeSymmetricEigen(MatrixUpTo6(jointBlocks_[i].topLeftCorner(m, m)));
      jointBlocks_[i].topLeftCorner(m, m) = extra.vectors *
                                            extra.values.cwiseMax(0).asDiagonal() *
                                            extra.vectors.transpose();
    }
    for (CoupledLink& coupled : coupledLinks_) coupled.ownWithout = own_[coupled.link];
    JoinCouplingStiffness(true);
    ++gaussNewtonTreeFactorizations_;
    factorized = treeSolver_.Factorize(TreeSystem(), false, &failedLink) ||
                 treeSolver_.Factorize(TreeSystem(), true, &failedLink);
  }
  if (!factorized) {
    reason = "the articulated actor's Hessian has no positive definite modification (tree recursion, pivot of "
             "the joint of link " +
             std::to_string(failedLink) + ": not finite, or zero with a zero Hessian)";
    return false;
  }
  // coupled with other bodies: their block gets the Schur complement's term
  if (!couplingDofs_.empty()) {
    ComputeSchurTerm();
    assembler.AddToAssembledBlock(contributor, -schurTerm_);
  }
  return true;
}

void ArticulatedActor::JoinCouplingStiffness(bool join) {
  for (CoupledLink const& coupled : coupledLinks_)
    own_[coupled.link] = join ? Matrix6(coupled.ownWithout + coupled.stiffness) : coupled.ownWithout;
}

void ArticulatedActor::ComputeSchurTerm() {
  // C A⁻¹ Cᵀ, C = Σ_ℓ W_ℓᵀ B_ℓ: for each coupled link ℓ' and each of the six
  // unit wrenches e_k on its frame, y = A⁻¹ B_ℓ'ᵀ e_k (one tree solve, O(N)),
  // then column k of Σ_ℓ W_ℓᵀ (B_ℓ y) (O(path) per link)
  schurTerm_.setZero();
  for (CoupledLink const& right : coupledLinks_) {
    for (int k = 0; k < 6; ++k) {
      treeRhs_.setZero();
      for (std::size_t j = 0; j < right.dofs.size(); ++j)
        treeRhs_[right.dofs[j]] = right.jacobian(k, static_cast<Eigen::Index>(j));
      SolveTree();
      schurColumns_.col(k).setZero();
      for (CoupledLink const& left : coupledLinks_)
        schurColumns_.col(k).noalias() += left.coupling.transpose() * LinkMotion(left);
    }
    schurTerm_.noalias() += schurColumns_ * right.coupling;
  }
}

Vector6 ArticulatedActor::LinkMotion(CoupledLink const& coupled) const {
  Vector6 motion = Vector6::Zero();
  for (std::size_t j = 0; j < coupled.dofs.size(); ++j)
    motion += coupled.jacobian.col(static_cast<Eigen::Index>(j)) * treeSolution_[coupled.dofs[j]];
  return motion;
}

void ArticulatedActor::SolveTree() {
  treeSolver_.Solve(TreeSystem(), Span<real const>(treeRhs_.data(), treeRhs_.size()),
                    Span<real>(treeSolution_.data(), treeSolution_.size()));
}

void ArticulatedActor::EliminateFromRhs(Span<real> rhs) {
  if (couplingDofs_.empty()) return;
  // rhs_o −= C A⁻¹ rhs_t = Σ_ℓ W_ℓᵀ B_ℓ y, y = A⁻¹ rhs_t
  for (int i = 0; i < numDofs_; ++i) treeRhs_[i] = rhs[dofOffset_ + i];
  SolveTree();
  for (CoupledLink const& coupled : coupledLinks_) {
    Vector6 const motion = LinkMotion(coupled);
    for (std::size_t j = 0; j < couplingDofs_.size(); ++j)
      rhs[couplingDofs_[j]] -= coupled.coupling.col(static_cast<Eigen::Index>(j)).dot(motion);
  }
}

void ArticulatedActor::Solve(Span<real const> rhs, Span<real> delta) {
  Span<real> const own = delta.subspan(dofOffset_, numDofs_);
  if (couplingDofs_.empty()) {
    treeSolver_.Solve(TreeSystem(), rhs.subspan(dofOffset_, numDofs_), own);
    return;
  }
  // x_t = A⁻¹(rhs_t − Cᵀ x_o), Cᵀ x_o = Σ_ℓ B_ℓᵀ (W_ℓ x_o): the other
  // bodies' solution as a wrench on each coupled link
  for (int i = 0; i < numDofs_; ++i) treeRhs_[i] = rhs[dofOffset_ + i];
  for (CoupledLink const& coupled : coupledLinks_) {
    Vector6 wrench = Vector6::Zero();
    for (std::size_t j = 0; j < couplingDofs_.size(); ++j)
      wrench += coupled.coupling.col(static_cast<Eigen::Index>(j)) * delta[couplingDofs_[j]];
    for (std::size_t j = 0; j < coupled.dofs.size(); ++j)
      treeRhs_[coupled.dofs[j]] -= coupled.jacobian.col(static_cast<Eigen::Index>(j)).dot(wrench);
  }
  treeSolver_.Solve(TreeSystem(), Span<real const>(treeRhs_.data(), treeRhs_.size()), own);
}

void ArticulatedActor::ModifyHessianToPositiveDefinite() const {
  // Eigen's pivoted LDLᵀ, H = Pᵀ L D Lᵀ P; each pivot replaced by its
  // magnitude, floored at 1e-10 of the largest: H₊ = Pᵀ L |D|₊ Lᵀ P, equal
  // to H where H is positive definite, keeping the curvature's magnitude
  // where it is not (a modified Cholesky). Only the changed pivots enter:
  // H₊ = H + Σₖ (|Dₖ|₊ − Dₖ) (Pᵀ lₖ)(Pᵀ lₖ)ᵀ, a rank update per negative pivot
  int const n = static_cast<int>(hessian_.rows());
  if (n == 0) return;
  modifiedFactor_.compute(hessian_);
  auto const pivots = modifiedFactor_.vectorD();
  real const floor = 1e-10 * pivots.cwiseAbs().maxCoeff();
  // P x = x[order]: the transpositions applied to the identity order
  auto const& transpositions = modifiedFactor_.transpositionsP();
  for (int i = 0; i < n; ++i) modifiedOrder_[i] = i;
  for (int k = 0; k < n; ++k) std::swap(modifiedOrder_[k], modifiedOrder_[transpositions.coeff(k)]);
  auto const& factor = modifiedFactor_.matrixLDLT();  // L strictly below the diagonal
  for (int k = 0; k < n; ++k) {
    real const change = std::max(std::abs(pivots[k]), floor) - pivots[k];
    if (change <= 0) continue;
    // Pᵀ lₖ: lₖ(i) goes to row order[i]; lₖ(k) = 1, lₖ(i < k) = 0
    modifiedColumn_.setZero();
    modifiedColumn_[modifiedOrder_[k]] = 1;
    for (int i = k + 1; i < n; ++i) modifiedColumn_[modifiedOrder_[i]] = factor(i, k);
    hessian_.noalias() += change * modifiedColumn_ * modifiedColumn_.transpose();
  }
}

void ArticulatedActor::SaveIterate() { saved_ = state_.joints; }

void ArticulatedActor::RestoreIterate() { state_.joints = saved_; }

void ArticulatedActor::ApplyIncrementFromSaved(Span<real const> delta, real alpha) {
  ApplyLocalIncrement(delta.data() + dofOffset_, alpha);
}

void ArticulatedActor::ApplyLocalIncrement(real const* d, real alpha) {
  for (int i = 0; i < GetNumLinks(); ++i) state_.joints[i] = Advance(i, saved_[i], d + links_[i].dofStart, alpha);
}

ArticulatedActor::JointState ArticulatedActor::Advance(int link, JointState const& q, real const* x,
                                                       real alpha) const {
  JointState to = q;
  switch (links_[link].joint) {
    case JointType::Revolute:
    case JointType::Prismatic: to.scalar = q.scalar + alpha * x[0]; break;
    case JointType::Spherical: to.rotation = (q.rotation * Exp(alpha * Real3(x[0], x[1], x[2]))).normalized(); break;
    case JointType::Free:
      to.translation = q.translation + alpha * Real3(x[0], x[1], x[2]);
      to.rotation = (q.rotation * Exp(alpha * Real3(x[3], x[4], x[5]))).normalized();
      break;
    case JointType::Fixed: break;
  }
  return to;
}

bool ArticulatedActor::IsStateFinite() const {
  for (JointState const& q : state_.joints)
    if (!std::isfinite(q.scalar) || !q.translation.allFinite() || !q.rotation.coeffs().allFinite()) return false;
  return true;
}

void ArticulatedActor::EndStage() {
  UpdateKinematics(false);
  for (int i = 0; i < GetNumLinks(); ++i)
    inertia_[i].End(kinematics_.com[i], kinematics_.linkRotation[i], state_.links[i]);
  // joint velocities: (Δq − c Δₚ)/(β h) in increment coordinates
  real const betaH = stage_.beta * stage_.duration;
  state_.previousJointVelocity = state_.jointVelocity;
  for (int i = 0; i < GetNumLinks(); ++i) {
    Link const& l = links_[i];
    real d[6], previous[6] = {0, 0, 0, 0, 0, 0};
    JointDifference(i, state_.joints[i], stageStart_[i], d);
    if (stage_.usesHistory) JointDifference(i, state_.previousJoints[i], stageStart_[i], previous);
    for (int a = 0; a < l.numDofs; ++a)
      state_.jointVelocity[l.dofStart + a] = (d[a] - stage_.cPrevious * previous[a]) / betaH;
  }
  state_.previousJoints = stageStart_;
  state_.hasHistory = true;
  state_.lastStageDuration = stage_.duration;
}

void ArticulatedActor::SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const {
  internal::SaveStateSnapshot(state_, snapshot);
}

void ArticulatedActor::RestoreSnapshot(internal::ActorSnapshot const& snapshot) {
  internal::RestoreStateSnapshot(snapshot, state_);
}

}  // namespace superdex
