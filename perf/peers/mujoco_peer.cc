// MuJoCo (libmujoco-dev 2.2.2) in perf/peers: each scene an MJCF string
// loaded by mj_loadXML from the virtual file system, stepped by mj_step.
//
// The model's options are MuJoCo's defaults (Euler integrator, Newton
// solver, pyramidal friction cone, default solref/solimp: soft contacts)
// except the time step and the scenes' gravity along −y; every geom has
// condim 3 and friction 0.5 (two geoms combine by the larger friction, so
// the contact has 0.5). Three variants: mujoco (impratio 1, the default),
// mujoco-impratio100 (friction constraints 100 times stiffer than the
// normal's: the setting MuJoCo offers against the slip of its soft
// frictional contacts) and mujoco-elliptic-impratio100 (the same with the
// elliptic cone instead of the default pyramidal one).
//
// Poses are read from qpos, not xpos: after mj_step, xpos and xmat still
// hold the kinematics computed at the step's start.
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstring>
#include <sstream>

#include "peer_scenes.h"

namespace {

class MujocoWorld final : public peers::World {
 public:
  MujocoWorld(mjModel* model, mjData* data) : model_(model), data_(data) {}
  ~MujocoWorld() override {
    mj_deleteData(data_);
    mj_deleteModel(model_);
  }

  mjData* Data() { return data_; }

  bool Step(std::string& why) override {
    mj_step(model_, data_);
    // a diverging state is reset by MuJoCo with a warning: report it as a failed step
    if (data_->warning[mjWARN_BADQACC].number > 0) {
      why = "MuJoCo reset a bad acceleration (mjWARN_BADQACC)";
      return false;
    }
    return true;
  }

  double LastIterations() const override { return data_->solver_iter; }

  peers::Pose BoxPose(int i) const override {
    // box i is body i + 1 (body 0 is the world), with one free joint: 3 positions then the
    // quaternion (w x y z)
    mjtNum const* q = data_->qpos + model_->jnt_qposadr[model_->body_jntadr[i + 1]];
    peers::Pose pose;
    for (int k = 0; k < 3; ++k) pose.position[k] = q[k];
    pose.rotation = peers::FromQuaternion(q[3], q[4], q[5], q[6]);
    return pose;
  }

 private:
  mjModel* model_;
  mjData* data_;
};

/// The model of `xml` (its bodies in document order), or null and `why`.
std::unique_ptr<MujocoWorld> Load(std::string const& xml, std::string& why) {
  // mjVFS holds 2000 file names of 1000 characters: too large for the stack
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  char const* name = "peer.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    why = "mj_makeEmptyFileVFS failed";
    return nullptr;
  }
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name)], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* model = mj_loadXML(name, vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!model) {
    why = std::string("mj_loadXML: ") + error;
    return nullptr;
  }
  return std::make_unique<MujocoWorld>(model, mj_makeData(model));
}

/// MuJoCo's options of one variant.
struct Options {
  double impratio = 1;
  bool elliptic = false;
};

/// The MJCF around `bodies` (worldbody content) at time step dt.
std::string Model(double dt, Options const& options, std::string const& bodies) {
  std::ostringstream xml;
  xml.precision(17);
  xml << "<mujoco model=\"peer\">\n"
      << "  <option timestep=\"" << dt << "\" gravity=\"0 " << -peers::kGravity
      << " 0\" impratio=\"" << options.impratio << "\" cone=\""
      << (options.elliptic ? "elliptic" : "pyramidal") << "\"/>\n"
      << "  <default><geom condim=\"3\" friction=\"" << peers::kFriction
      << " 0.005 0.0001\"/></default>\n"
      << "  <worldbody>\n"
      << bodies << "  </worldbody>\n"
      << "</mujoco>\n";
  return xml.str();
}

/// A free 1 kg box body (MuJoCo computes the solid box's inertia from the geom).
std::string FreeBox(double half, peers::Vec3 const& p, double qw = 1, double qz = 0) {
  std::ostringstream xml;
  xml.precision(17);
  xml << "    <body pos=\"" << p[0] << " " << p[1] << " " << p[2] << "\" quat=\"" << qw << " 0 0 "
      << qz << "\">"
      << "<joint type=\"free\"/><geom type=\"box\" size=\"" << half << " " << half << " " << half
      << "\" mass=\"1\"/></body>\n";
  return xml.str();
}

std::unique_ptr<peers::World> Incline(double tanTheta, double dt, Options const& options,
                                      std::string& why) {
  double const theta = std::atan(tanTheta);
  double const nx = -std::sin(theta), ny = std::cos(theta);  // R_z(θ)·ŷ
  double const up = peers::kInclineHalf + peers::kInclineGap;
  std::ostringstream bodies;
  bodies.precision(17);
  // a plane's normal is its frame's z axis; its size only matters for rendering
  bodies << "    <geom type=\"plane\" size=\"10 10 0.1\" zaxis=\"" << nx << " " << ny << " 0\"/>\n"
         << FreeBox(peers::kInclineHalf, {nx * up, ny * up, 0}, std::cos(theta / 2),
                    std::sin(theta / 2));
  return Load(Model(dt, options, bodies.str()), why);
}

std::unique_ptr<peers::World> Stack(double dt, Options const& options, std::string& why) {
  std::string bodies = "    <geom type=\"plane\" size=\"10 10 0.1\" zaxis=\"0 1 0\"/>\n";
  for (int i = 0; i < peers::kStackCount; ++i)
    bodies += FreeBox(peers::kStackHalf, {0, peers::StackHeight(i), 0});
  return Load(Model(dt, options, bodies), why);
}

std::unique_ptr<peers::World> FastBox(double dt, Options const& options, std::string& why) {
  std::ostringstream bodies;
  bodies.precision(17);
  auto const& p = peers::kPlateHalf;
  bodies << "    <geom type=\"box\" size=\"" << p[0] << " " << p[1] << " " << p[2] << "\"/>\n"
         << FreeBox(peers::kFastHalf, {0, peers::kFastHeight, 0});
  std::unique_ptr<MujocoWorld> world = Load(Model(dt, options, bodies.str()), why);
  // a free joint's first three velocities are the linear velocity in the world frame
  if (world) world->Data()->qvel[1] = -peers::kFastSpeed;
  return world;
}

peers::PeerEngine Variant(std::string const& name, Options const& options) {
  peers::PeerEngine e;
  e.name = name;
  e.note = std::string("MuJoCo ") + mj_versionString() +
           "; defaults (Euler; Newton solver; solref 0.02 1; " +
           "solimp defaults); condim 3 friction 0.5; " +
           (options.elliptic ? "elliptic" : "pyramidal") + " cone; impratio " +
           std::to_string(static_cast<int>(options.impratio));
  e.incline = [options](double tanTheta, double dt, std::string& why) {
    return Incline(tanTheta, dt, options, why);
  };
  e.stack = [options](double dt, std::string& why) { return Stack(dt, options, why); };
  e.fastBox = [options](double dt, std::string& why) { return FastBox(dt, options, why); };
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  return peers::RunPeers({Variant("mujoco", {}), Variant("mujoco-impratio100", {100, false}),
                          Variant("mujoco-elliptic-impratio100", {100, true})},
                         argc, argv);
}
