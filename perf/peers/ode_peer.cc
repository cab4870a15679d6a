// ODE (libode-dev 0.16.2, double precision) in perf/peers: a dWorld with
// a simple space of dBox / dPlane geoms; every step collides the space,
// makes a contact joint per contact point (up to 8 per pair), steps the
// world and empties the contact group.
//
// Two variants: ode-step (dWorldStep, the direct "big matrix" LCP solver)
// and ode-quickstep (dWorldQuickStep, the iterative SOR solver, its default
// 20 iterations). World ERP 0.2 and CFM 1e-5 are ODE's defaults; contacts
// carry no softness of their own. The contact mode is dContactApprox1:
// without it ODE's mu is a force limit in newtons, not a Coulomb coefficient
// (a 1 kg box would hold 0.5 N whatever its load); with it the friction
// pyramid is mu times the contact's normal force. The first friction
// direction is ODE's default (in the x–y plane for the incline's normal, so
// along the slope).
#include <ode/ode.h>

#include <cmath>

#include "peer_scenes.h"

namespace {

enum class Stepper { Direct, Quick };

class OdeWorld final : public peers::World {
 public:
  OdeWorld(double dt, Stepper stepper)
      : world_(dWorldCreate()),
        space_(dSimpleSpaceCreate(nullptr)),
        contacts_(dJointGroupCreate(0)),
        dt_(dt),
        stepper_(stepper) {
    dWorldSetGravity(world_, 0, -peers::kGravity, 0);
  }

  ~OdeWorld() override {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);  // destroys its geoms
    dWorldDestroy(world_);
  }

  dSpaceID Space() const { return space_; }

  /// A dynamic box of full sides 2·half, 1 kg (solid box inertia), at `position` turned by
  /// `rotation`.
  dBodyID AddBox(peers::Vec3 const& half, peers::Vec3 const& position,
                 peers::Mat3 const& rotation) {
    dBodyID const body = dBodyCreate(world_);
    dMass mass;
    dMassSetBoxTotal(&mass, 1, 2 * half[0], 2 * half[1], 2 * half[2]);
    dBodySetMass(body, &mass);
    dBodySetPosition(body, position[0], position[1], position[2]);
    dMatrix3 r{};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) r[4 * a + b] = rotation[a][b];
    dBodySetRotation(body, r);
    dGeomID const geom = dCreateBox(space_, 2 * half[0], 2 * half[1], 2 * half[2]);
    dGeomSetBody(geom, body);
    boxes_.push_back(body);
    return body;
  }

  bool Step(std::string& why) override {
    dSpaceCollide(space_, this, &OdeWorld::NearCallback);
    int const ok =
        stepper_ == Stepper::Direct ? dWorldStep(world_, dt_) : dWorldQuickStep(world_, dt_);
    dJointGroupEmpty(contacts_);
    if (!ok) why = "dWorldStep returned 0 (out of memory)";
    return ok != 0;
  }

  peers::Pose BoxPose(int i) const override {
    dReal const* p = dBodyGetPosition(boxes_.at(i));
    dReal const* r = dBodyGetRotation(boxes_.at(i));  // 3 rows of 4
    peers::Pose pose;
    for (int a = 0; a < 3; ++a) {
      pose.position[a] = p[a];
      for (int b = 0; b < 3; ++b) pose.rotation[a][b] = r[4 * a + b];
    }
    return pose;
  }

 private:
  static void NearCallback(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<OdeWorld*>(data);
    constexpr int kMaxContacts = 8;  // a box–box face contact has up to 8 points, box–plane 4
    dContact contact[kMaxContacts]{};
    int const n = dCollide(a, b, kMaxContacts, &contact[0].geom, sizeof(dContact));
    for (int k = 0; k < n; ++k) {
      contact[k].surface.mode = dContactApprox1;
      contact[k].surface.mu = peers::kFriction;
      contact[k].surface.bounce = 0;
      dJointID const joint = dJointCreateContact(self->world_, self->contacts_, &contact[k]);
      dJointAttach(joint, dGeomGetBody(a), dGeomGetBody(b));
    }
  }

  dWorldID world_;
  dSpaceID space_;
  dJointGroupID contacts_;
  double dt_;
  Stepper stepper_;
  std::vector<dBodyID> boxes_;
};

std::unique_ptr<peers::World> Incline(double tanTheta, double dt, Stepper stepper) {
  auto world = std::make_unique<OdeWorld>(dt, stepper);
  double const theta = std::atan(tanTheta);
  peers::Mat3 const tilt = peers::RotationZ(theta);
  peers::Vec3 const normal{tilt[0][1], tilt[1][1], tilt[2][1]};
  dCreatePlane(world->Space(), normal[0], normal[1], normal[2], 0);  // n·x = 0: through the origin
  double const up = peers::kInclineHalf + peers::kInclineGap;
  double const h = peers::kInclineHalf;
  world->AddBox({h, h, h}, {normal[0] * up, normal[1] * up, 0}, tilt);
  return world;
}

std::unique_ptr<peers::World> Stack(double dt, Stepper stepper) {
  auto world = std::make_unique<OdeWorld>(dt, stepper);
  dCreatePlane(world->Space(), 0, 1, 0, 0);
  double const h = peers::kStackHalf;
  for (int i = 0; i < peers::kStackCount; ++i)
    world->AddBox({h, h, h}, {0, peers::StackHeight(i), 0}, peers::kIdentity);
  return world;
}

std::unique_ptr<peers::World> FastBox(double dt, Stepper stepper) {
  auto world = std::make_unique<OdeWorld>(dt, stepper);
  auto const& p = peers::kPlateHalf;
  dCreateBox(world->Space(), 2 * p[0], 2 * p[1], 2 * p[2]);  // no body: static, at the origin
  double const h = peers::kFastHalf;
  dBodyID const box = world->AddBox({h, h, h}, {0, peers::kFastHeight, 0}, peers::kIdentity);
  dBodySetLinearVel(box, 0, -peers::kFastSpeed, 0);
  return world;
}

peers::PeerEngine Variant(Stepper stepper) {
  peers::PeerEngine e;
  bool const direct = stepper == Stepper::Direct;
  e.name = direct ? "ode-step" : "ode-quickstep";
  e.note = std::string("ODE 0.16.2 double; ") +
           (direct ? "dWorldStep" : "dWorldQuickStep 20 iterations") +
           "; ERP 0.2 CFM 1e-5 (defaults); dContactApprox1 mu 0.5; up to 8 contacts per pair";
  e.incline = [stepper](double tanTheta, double dt, std::string&) {
    return Incline(tanTheta, dt, stepper);
  };
  e.stack = [stepper](double dt, std::string&) { return Stack(dt, stepper); };
  e.fastBox = [stepper](double dt, std::string&) { return FastBox(dt, stepper); };
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  // ODE's global data (the collision tables) before any world; closed after all
  if (!dInitODE2(0) || !dAllocateODEDataForThread(dAllocateMaskAll)) return 1;
  int const status =
      peers::RunPeers({Variant(Stepper::Direct), Variant(Stepper::Quick)}, argc, argv);
  dCloseODE();
  return status;
}
