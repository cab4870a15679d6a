// PETSc's process lifetime with the PCG backend, one mode per ctest test:
//   own                 SuperDex starts MPI and PETSc and finalizes both at exit
//   host-mpi            the host owns MPI; PETSc is finalized inside its MPI_Finalize
//   host-mpi-late-scene a scene outlives the host's MPI_Finalize (static
//                       storage): its solver must skip PETSc's destroy calls
//   host-petsc          the host owns PETSc; SuperDex neither initializes nor
//                       finalizes it
// Each mode steps a small beam with PCG + GAMG and exits 0; any crash, MPI
// abort or PETSc error at exit fails the test.
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include <mpi.h>
#include <petscsys.h>

#include <superdex/linsolve/petsc_runtime.h>
#include <superdex/superdex.h>

using namespace superdex;

namespace {

std::unique_ptr<Scene> lateScene;  // destroyed after main returns

bool Check(bool condition, char const* what) {
  if (!condition) std::fprintf(stderr, "petsc_lifetime_test: FAILED: %s\n", what);
  return condition;
}

// a 4 × 1 × 1-cell beam clamped at x = 0, stepped 3 times with PCG + GAMG
std::unique_ptr<Scene> SteppedScene() {
  Error error;
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscPcg;
  auto scene = Scene::Create(params, error);
  TetMesh mesh;
  if (!scene || !MakeTetBox(Real3::Zero(), Real3(0.4, 0.1, 0.1), {4, 1, 1}, mesh, error)) return nullptr;
  DeformableActorParams beamParams;
  beamParams.nodes = mesh.nodes;
  beamParams.tetrahedra = mesh.tetrahedra;
  DeformableActor* beam = scene->CreateDeformableActor(beamParams, error);
  if (!beam) return nullptr;
  for (int i = 0; i < beam->GetNumNodes(); ++i) {
    if (beam->GetNodeReferencePosition(i).x() > 1e-9) continue;
    DeformableNodePositionConstraintParams pin;
    pin.actor = beam->GetHandle();
    pin.nodeIndex = i;
    pin.position = beam->GetNodePosition(i);
    pin.stiffness = 1e6;
    if (!scene->CreateDeformableNodePositionConstraint(pin, error)) return nullptr;
  }
  for (int step = 0; step < 3; ++step) {
    if (!scene->Step(0.01, error)) {
      std::fprintf(stderr, "petsc_lifetime_test: %s\n", error.ToString().c_str());
      return nullptr;
    }
  }
  return scene;
}

}  // namespace

int main(int argc, char** argv) {
  std::string const mode = argc > 1 ? argv[1] : "";
  if (mode == "own") {
    bool ok = Check(SteppedScene() != nullptr, "stepping with PCG");
    int mpiInitialized = 0;
    MPI_Initialized(&mpiInitialized);
    ok = Check(mpiInitialized == 1, "PETSc started MPI") && ok;
    return ok ? 0 : 1;  // PETSc and MPI are finalized at exit
  }
  if (mode == "host-mpi" || mode == "host-mpi-late-scene") {
    MPI_Init(&argc, &argv);
    bool ok = true;
    if (mode == "host-mpi") {
      ok = Check(SteppedScene() != nullptr, "stepping with PCG") && ok;
    } else {
      lateScene = SteppedScene();
      ok = Check(lateScene != nullptr, "stepping with PCG") && ok;
    }
    ok = Check(!internal::IsPetscFinalized(), "PETSc alive before MPI_Finalize") && ok;
    MPI_Finalize();
    ok = Check(internal::IsPetscFinalized(), "PETSc finalized within MPI_Finalize") && ok;
    return ok ? 0 : 1;
  }
  if (mode == "host-petsc") {
    PetscInitialize(&argc, &argv, nullptr, nullptr);
    bool ok = Check(SteppedScene() != nullptr, "stepping with PCG");
    ok = Check(!internal::IsPetscFinalized(), "PETSc left to the host") && ok;
    PetscFinalize();
    return ok ? 0 : 1;
  }
  std::fprintf(stderr, "usage: petsc_lifetime_test own|host-mpi|host-mpi-late-scene|host-petsc\n");
  return 2;
}
