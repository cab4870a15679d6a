// NodalActor: the common face of actors made of nodes with a world position —
// deformable solids and shells (DeformableActor) and rods (RodActor). The
// deformable couplings of constraints.md (DeformableNodePosition,
// DeformableNodeToDeformableNode, DeformableNodeToRigid) act on any nodal
// actor: node i's position T(X + u) is linear in its 3 displacement DoFs u,
// which start at local DoF GetNodeDofStride()·i (3 for solids and shells, 4
// for rods, whose 4th DoF is the twist).
#pragma once

#include <superdex/actors/actor.h>

namespace superdex {

class NodalActor : public Actor {
 public:
  virtual int GetNumNodes() const = 0;
  /// World position T(X + u) of node i, 0 <= i < GetNumNodes().
  virtual Real3 GetNodePosition(int i) const = 0;
  /// World-frame velocity of node i.
  virtual Real3 GetNodeVelocity(int i) const = 0;
  /// Reference position X of node i (actor frame): the rest shape.
  virtual Real3 const& GetNodeReferencePosition(int i) const = 0;
  /// Lumped mass of node i [kg].
  virtual real GetNodeMass(int i) const = 0;
  /// Rotation of the actor transform T (u is in the actor frame; identity for rods).
  virtual Quat const& GetTransformRotation() const = 0;
  /// Number of DoFs per node; node i's displacement is at local DoFs stride·i + {0, 1, 2}.
  int GetNodeDofStride() const { return nodeDofStride_; }
  /// The local DoFs of node i's displacement: stride·i + {0, 1, 2}.
  DynamicArray<int> GetNodePositionDofs(int i) const {
    return {nodeDofStride_ * i, nodeDofStride_ * i + 1, nodeDofStride_ * i + 2};
  }

 protected:
  NodalActor(ActorType type, int numNodes, int nodeDofStride)
      : Actor(type, nodeDofStride * numNodes), nodeDofStride_(nodeDofStride) {}

 private:
  int nodeDofStride_;
};

}  // namespace superdex
