// The per-frame loops allocate nothing. Two guards: Eigen's runtime check (this target compiles
// the dynamics sources itself with EIGEN_RUNTIME_NO_MALLOC, see CMakeLists.txt), which aborts on
// any Eigen heap allocation while disallowed, and a count of every global operator new
// (std::vector, std::string, std::function…) around the loops.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "acro/dynamics/inverse_dynamics.h"
#include "standard_human_fixture.h"
#include "test_models.h"

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "this test needs EIGEN_RUNTIME_NO_MALLOC"
#endif

namespace {
std::atomic<long> g_news{0};
}  // namespace

// The replaced operator new uses malloc, so the replaced operator delete must use free; GCC's
// -Wmismatched-new-delete cannot see that the pair is replaced consistently and warns where it
// inlines them.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(std::size_t size) {
  ++g_news;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace acro::dynamics {
namespace {

// Runs every per-frame algorithm once on (q, v, a).
void RunFrame(const Model<double>& model,
              Workspace<double>& ws,
              const Eigen::VectorXd& q,
              const Eigen::VectorXd& v,
              Eigen::VectorXd& a,
              const std::vector<SpatialForce<double>>& F_ext,
              Matrix3X<double>& Jp,
              Matrix6X<double>& Jb,
              Eigen::VectorXd& qdot,
              Eigen::VectorXd& q_next,
              double& sink) {
  sink += CalcInverseDynamics(model, ws, q, v, a)[0];
  sink += CalcRootResidual(model, ws, 1.75).force_per_weight[2];
  sink += CalcRootWrenchWithJointChanged(model, ws, model.num_segments() - 1, v, a).rotational()[0];
  sink += CalcInverseDynamicsAtSameConfiguration(model, ws, v, a)[0];
  sink += CalcInverseDynamics(model, ws, q, v, a, &F_ext)[6];
  sink += CalcBiasForces(model, ws, q, v)[1];
  sink += CalcMassMatrix(model, ws, q)(0, 0);
  CalcForwardKinematics(model, ws, q);
  CalcForwardKinematics(model, ws, q, v);
  for (int p = 0; p < model.num_points(); ++p) {
    sink += CalcPointPosition(model, ws, p)[0] + CalcPointVelocity(model, ws, p)[1];
    CalcPointJacobian(model, ws, p, Jp);
    sink += Jp(0, 0);
  }
  for (int b = 0; b < model.num_segments(); ++b) {
    CalcSegmentJacobian(model, ws, b, Jb);
    sink += Jb(3, 0) + CalcSegmentSpatialVelocity(ws, b).rotational()[0];
  }
  sink += CalcCenterOfMassPosition(model, ws)[2] + CalcCenterOfMassVelocity(model, ws)[2];
  CalcCenterOfMassJacobian(model, ws, Jp);
  sink += Jp(2, 6);
  sink += CalcCentroidalMomentum(model, ws).rotational()[0];
  sink += CalcCenterOfMassAcceleration(model, ws, q, v, a)[2];
  CalcFlightRootAcceleration(model, ws, q, v, a);
  sink += a[0];
  CalcConfigurationDerivative(model, q, v, qdot);
  IntegrateConfiguration(model, q, v, 1e-3, q_next);
  sink += qdot[3] + q_next[3];
}

TEST(NoMallocTest, PerFrameLoopsDoNotAllocate) {
  std::mt19937 rng(1);
  std::vector<Model<double>> models = {testing::MakeStandardHuman(),
                                       testing::MakeRandomTree(rng, 20, 3)};
  for (const Model<double>& model : models) {
    // Everything the loop needs, allocated up front.
    Workspace<double> ws(model);
    std::vector<Eigen::VectorXd> qs, vs, as;
    for (int f = 0; f < 10; ++f) {
      qs.push_back(testing::RandomConfiguration(model, rng));
      vs.push_back(testing::RandomVelocity(model, rng, 2.0));
      as.push_back(testing::RandomVelocity(model, rng, 5.0));
    }
    std::vector<SpatialForce<double>> F_ext(static_cast<size_t>(model.num_segments()),
                                            SpatialForce<double>::Zero());
    Matrix3X<double> Jp(3, model.nv());
    Matrix6X<double> Jb(6, model.nv());
    Eigen::VectorXd qdot(model.nq()), q_next(model.nq());
    double sink = 0.0;

    const long news_before = g_news.load();
    Eigen::internal::set_is_malloc_allowed(false);
    for (int f = 0; f < 10; ++f) {
      RunFrame(model, ws, qs[f], vs[f], as[f], F_ext, Jp, Jb, qdot, q_next, sink);
    }
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_EQ(g_news.load() - news_before, 0) << "operator new called in the per-frame loop";
    EXPECT_TRUE(std::isfinite(sink));
  }
}

// The guard is armed: an Eigen allocation while disallowed is caught (death test), so the test
// above can fail.
TEST(NoMallocTest, GuardIsArmed) {
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        Eigen::VectorXd x(100);
        x.setZero();
      },
      "");
}

}  // namespace
}  // namespace acro::dynamics
