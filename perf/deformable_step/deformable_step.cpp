// Where a step's time goes on a clamped tetrahedral beam: assembly (element
// energy, gradient and projected Hessian + scatter), symbolic analysis,
// factorization, solve, line search — with the solver the scene reports.
//
//   superdex_deformable_step [cellsX cellsY cellsZ] [steps] [material: snh|linear]
//                            [solver: cholmod|jacobi|pbjacobi|bjacobi|icc|gamg|hypre]
//
// The beam is 1 × 0.2 × 0.2 m, E = 1e5, ν = 0.3, ρ = 1000, clamped at x = 0,
// dt = 1/60, backward Euler; the first step (pattern build + analysis) is
// reported separately from the mean of the others.
#include <superdex/superdex.h>

#include <cstdio>
#include <cstdlib>
#include <string>

using namespace superdex;

int main(int argc, char** argv) {
  std::array<int, 3> cells{70, 16, 16};
  int steps = 3;
  TetMaterialModel material = TetMaterialModel::StableNeoHookean;
  if (argc >= 4)
    for (int i = 0; i < 3; ++i) cells[i] = std::atoi(argv[1 + i]);
  if (argc >= 5) steps = std::atoi(argv[4]);
  if (argc >= 6 && std::string(argv[5]) == "linear") material = TetMaterialModel::LinearElastic;
  SceneParams params;
  params.linearSolver = LinearSolverType::Cholmod;
  if (argc >= 7 && std::string(argv[6]) != "cholmod") {
    std::string const name = argv[6];
    params.linearSolver = LinearSolverType::PetscPcg;
    params.pcg.preconditioner = name == "jacobi"     ? PcgPreconditioner::Jacobi
                                : name == "pbjacobi" ? PcgPreconditioner::PointBlockJacobi
                                : name == "bjacobi"  ? PcgPreconditioner::BlockJacobi
                                : name == "icc"      ? PcgPreconditioner::Icc
                                : name == "hypre"    ? PcgPreconditioner::BoomerAmg
                                                     : PcgPreconditioner::Gamg;
    params.pcg.relativeTolerance = 1e-6;
  }

  Error error;
  TetMesh mesh;
  if (!MakeTetBox(Real3(0, -0.1, -0.1), Real3(1, 0.2, 0.2), cells, mesh, error)) {
    std::fprintf(stderr, "%s\n", error.ToString().c_str());
    return 1;
  }
  auto scene = Scene::Create(params, error);
  DeformableActorParams p;
  p.nodes = mesh.nodes;
  p.tetrahedra = mesh.tetrahedra;
  p.material = material;
  DeformableActor* beam = scene ? scene->CreateDeformableActor(p, error) : nullptr;
  if (!beam) {
    std::fprintf(stderr, "%s\n", error.ToString().c_str());
    return 1;
  }
  for (int i = 0; i < beam->GetNumNodes(); ++i) {
    if (beam->GetNodeReferencePosition(i).x() > 1e-9) continue;
    DeformableNodePositionConstraintParams pin;
    pin.actor = beam->GetHandle();
    pin.nodeIndex = i;
    pin.position = beam->GetNodePosition(i);
    pin.stiffness = 1e8;
    if (!scene->CreateDeformableNodePositionConstraint(pin, error)) {
      std::fprintf(stderr, "%s\n", error.ToString().c_str());
      return 1;
    }
  }
  BlasInfo const blas = GetBlasInfo();
  std::printf("beam %dx%dx%d cells: %d tets, %d DoFs, %s, BLAS %s/%s\n", cells[0], cells[1], cells[2],
              beam->GetNumTetrahedra(), beam->GetNumDofs(), std::string(ToString(material)).c_str(),
              blas.library.c_str(), blas.coreName.c_str());
  std::printf("%6s %6s %7s %9s %9s %9s %9s %9s %9s %8s\n", "step", "newton", "cg its", "total[s]", "assembly", "analysis",
              "factor", "solve", "linesrch", "asm %");
  double sums[6] = {0, 0, 0, 0, 0, 0};
  int newton = 0;
  for (int s = 0; s < steps; ++s) {
    if (!scene->Step(1.0 / 60, error)) {
      std::fprintf(stderr, "%s\n", error.ToString().c_str());
      return 1;
    }
    SceneStats const& st = scene->GetStats();
    double const phases[6] = {st.stepSeconds, st.assemblySeconds, st.analysisSeconds,
                              st.factorizationSeconds, st.solveSeconds, st.lineSearchSeconds};
    std::printf("%6d %6d %7d %9.3f %9.3f %9.3f %9.3f %9.3f %9.3f %7.1f%%\n", s + 1, st.newtonIterations,
                st.linearIterations, phases[0],
                phases[1], phases[2], phases[3], phases[4], phases[5], 100 * phases[1] / phases[0]);
    if (s > 0) {
      for (int k = 0; k < 6; ++k) sums[k] += phases[k];
      newton += st.newtonIterations;
    }
  }
  SceneStats const& st = scene->GetStats();
  std::printf("nnz(H) %lld, nnz(L) %.3g, factor flops %.3g, solver: %s\n",
              static_cast<long long>(st.hessianNonzeros), st.factorNonzeros, st.factorFlops,
              st.linearSolver.c_str());
  if (steps > 1) {
    std::printf("steps 2..%d mean: %.3f s/step, %.1f Newton its, assembly %.1f%%, factorization %.1f%%, "
                "solve %.1f%%, line search %.1f%%\n",
                steps, sums[0] / (steps - 1), double(newton) / (steps - 1), 100 * sums[1] / sums[0],
                100 * sums[3] / sums[0], 100 * sums[4] / sums[0], 100 * sums[5] / sums[0]);
  }
  return 0;
}
