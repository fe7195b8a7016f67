#include "acro/athlete/body_mesh.h"

#include <fstream>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "acro/athlete/de_leva.h"
#include "acro/base/input_error.h"
#include "refdata.h"

namespace acro::analysis {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDeg = std::numbers::pi / 180.0;

YeadonMeasurements Male1() {
  return ReadYeadonMeasurements(acro::testing::RefdataFile("yeadon/male1.txt"));
}

// Largest relative disagreement, over the 11 Yeadon segments, between the mesh-integrated and the
// analytic mass, centre of mass (relative to the segment's length) and inertia (Frobenius norm).
struct Disagreement {
  double mass = 0, com = 0, inertia = 0;
};
Disagreement CompareWithAnalytic(const YeadonHuman& human, const BodyMesh& mesh) {
  const std::vector<InertialProperties> parts = CalcMeshPartInertia(mesh);
  Disagreement worst;
  for (const YeadonSegment& seg : human.segments()) {
    std::vector<InertialProperties> mine;
    for (int s : seg.solids) {
      const std::string& label = human.solids()[static_cast<size_t>(s)].label;
      for (size_t p = 0; p < mesh.part_label.size(); ++p)
        if (mesh.part_label[p] == label) mine.push_back(parts[p]);
    }
    EXPECT_EQ(mine.size(), seg.solids.size());
    const InertialProperties m = CombineInertia(mine);
    const double length = (seg.p_HoBend_H - seg.p_HoBo_H).norm();
    worst.mass = std::max(worst.mass, std::abs(m.mass_kg / seg.in_H.mass_kg - 1.0));
    worst.com = std::max(worst.com, (m.p_HoCm_H - seg.in_H.p_HoCm_H).norm() / length);
    worst.inertia =
        std::max(worst.inertia, (m.I_Cm_H - seg.in_H.I_Cm_H).norm() / seg.in_H.I_Cm_H.norm());
  }
  return worst;
}

TEST(BodyMesh, WatertightAndWithinHalfAPercentOfTheAnalyticModel) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  YeadonConfiguration cfg;  // a posed body, so that orientation errors would show
  cfg.Set("PJ1extension", -60 * kDeg);
  cfg.Set("J1J2flexion", 80 * kDeg);
  cfg.Set("CB1abduction", 45 * kDeg);
  cfg.Set("TCspinalTorsion", 20 * kDeg);
  const YeadonHuman human = YeadonHuman::Make(Male1(), {}, cfg);
  const BodyMesh mesh =
      MakeBodyMesh(human, MakeAthleteBodyFromYeadon(human));  // 48 per half circle
  EXPECT_EQ(mesh.part_label.size(), human.solids().size());
  std::string why;
  EXPECT_TRUE(IsWatertight(mesh, &why)) << why;
  const Disagreement d = CompareWithAnalytic(human, mesh);
  RecordProperty("mass", std::to_string(d.mass));
  RecordProperty("com", std::to_string(d.com));
  RecordProperty("inertia", std::to_string(d.inertia));
  std::printf("default resolution: mass %.2e, com %.2e, inertia %.2e (relative, worst segment)\n",
              d.mass,
              d.com,
              d.inertia);
  EXPECT_LT(d.mass, 0.005);
  EXPECT_LT(d.com, 0.005);
  EXPECT_LT(d.inertia, 0.005);
  // The inscribed polyhedra converge: a coarser mesh is worse, by about the square of the ratio.
  BodyMeshOptions coarse;
  coarse.points_per_semicircle = 12;
  coarse.ellipsoid_bands = 8;
  const Disagreement c =
      CompareWithAnalytic(human, MakeBodyMesh(human, MakeAthleteBodyFromYeadon(human), coarse));
  EXPECT_GT(c.mass, 4 * d.mass);
  EXPECT_GT(c.inertia, 4 * d.inertia);
}

TEST(BodyMesh, ThePackagesConeCentroidsDisagreeWithTheGeometry) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  YeadonOptions package;
  package.package_compatible = true;
  const YeadonHuman human = YeadonHuman::Make(Male1(), package);
  const BodyMesh mesh = MakeBodyMesh(human, MakeAthleteBodyFromYeadon(human));
  // Same solids, same mesh: masses agree, but the centroids are off by far more than 0.5 %.
  const Disagreement d = CompareWithAnalytic(human, mesh);
  EXPECT_LT(d.mass, 0.005);
  EXPECT_GT(d.com, 0.01);
}

// The posed body's whole inertia two independent ways (issue "real-data fidelity", item 5): the
// analytic model (each solid's inertia in its frame S turned into H as R·I·Rᵀ, then the
// parallel-axis theorem) and the mesh integrated exactly part by part (which knows none of the
// model's formulas, only the solids' surfaces). male1 in a tuck, a quarter into a somersault as in
// flight: they agree to the mesh's resolution in mass, centre of mass, principal moments and
// every product of inertia — the product that a tensor turned the wrong way (Rᵀ·I·R, the yeadon
// package's defect, docs/athlete-model.md) gets wrong included. docs/athlete-model.md quotes the
// numbers printed here.
TEST(BodyMesh, APosedBodysInertiaIntegratedIsTheModels) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  YeadonConfiguration tuck;  // hips and knees flexed, arms forward round the shins
  tuck.Set("somersault", 45 * kDeg);
  tuck.Set("PJ1extension", -120 * kDeg);
  tuck.Set("PK1extension", -120 * kDeg);
  tuck.Set("J1J2flexion", 130 * kDeg);
  tuck.Set("K1K2flexion", 130 * kDeg);
  tuck.Set("CA1extension", -70 * kDeg);
  tuck.Set("CB1extension", -70 * kDeg);
  tuck.Set("A1A2extension", -60 * kDeg);
  tuck.Set("B1B2extension", -60 * kDeg);
  tuck.Set("TCsagittalSpinalFlexion", -20 * kDeg);
  const YeadonHuman human = YeadonHuman::Make(Male1(), {}, tuck);
  const BodyMesh mesh = MakeBodyMesh(human, MakeAthleteBodyFromYeadon(human));
  const InertialProperties integrated = CombineInertia(CalcMeshPartInertia(mesh));
  const InertialProperties& model = human.total();
  // In yeadon's axes (x left, y posterior, z up), as the package prints them.
  const Eigen::Matrix3d Y = YeadonAxesToBodyAxes().transpose();
  const auto principal = [](const Eigen::Matrix3d& I) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(I);
    return Eigen::Vector3d(eig.eigenvalues());  // ascending
  };
  for (const auto& [name, I_H] :
       {std::pair{"model", model.I_Cm_H}, {"integrated mesh", integrated.I_Cm_H}}) {
    const Eigen::Matrix3d I = Y * I_H * Y.transpose();
    const Eigen::Vector3d p = principal(I_H);
    std::printf(
        "%-16s I_xx %.4f I_yy %.4f I_zz %.4f I_xy %+.4f I_yz %+.4f I_xz %+.4f; "
        "principal %.4f %.4f %.4f kg m^2\n",
        name,
        I(0, 0),
        I(1, 1),
        I(2, 2),
        I(0, 1),
        I(1, 2),
        I(0, 2),
        p(0),
        p(1),
        p(2));
  }
  const Eigen::Vector3d pm = principal(model.I_Cm_H), pi = principal(integrated.I_Cm_H);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(pi(k) / pm(k), 1.0, 0.003) << k;
  // Every entry, products included, within 0.3 % of the largest principal moment; the large
  // posterior–up product within 0.3 % of itself.
  EXPECT_LT((integrated.I_Cm_H - model.I_Cm_H).cwiseAbs().maxCoeff(), 0.003 * pm.maxCoeff());
  const Eigen::Matrix3d Im = Y * model.I_Cm_H * Y.transpose();
  const Eigen::Matrix3d Ii = Y * integrated.I_Cm_H * Y.transpose();
  EXPECT_GT(std::abs(Im(1, 2)), 0.5);  // a tuck in flight: a large product
  EXPECT_NEAR(Ii(1, 2) / Im(1, 2), 1.0, 0.003);
  EXPECT_NEAR(integrated.mass_kg / model.mass_kg, 1.0, 0.003);
  EXPECT_LT((integrated.p_HoCm_H - model.p_HoCm_H).norm(), 0.001);
}

TEST(BodyMesh, SkinnedRestMeshFollowsThePosedModel) {
  ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("yeadon/male1.txt"));
  const YeadonHuman human = YeadonHuman::Make(Male1());
  const AthleteBody rest = MakeAthleteBodyFromYeadon(human);
  const BodyMesh mesh = MakeBodyMesh(human, rest);
  // Weights are a partition of unity; blended vertices exist near joints.
  int blended = 0;
  for (Eigen::Index i = 0; i < mesh.skin_weight.cols(); ++i) {
    EXPECT_NEAR(mesh.skin_weight.col(i).sum(), 1.0, 4 * kEps);
    blended += mesh.skin_segment(1, i) >= 0 ? 1 : 0;
  }
  EXPECT_GT(blended, 0);
  // Pose by the body's angles and by Yeadon's own angles: the vertices that follow one segment
  // land where the mesh of the Yeadon-posed human has them (same construction order).
  BodyPose pose;
  pose.angles_rad = {
      {"hip_flexion", 100 * kDeg}, {"knee_flexion", 70 * kDeg}, {"shoulder_flexion", 150 * kDeg}};
  const Eigen::Matrix3Xd skinned = CalcSkinnedVertices(mesh, rest, PoseAthleteBody(rest, pose));
  YeadonConfiguration cfg;
  cfg.Set("PJ1extension", -100 * kDeg);
  cfg.Set("PK1extension", -100 * kDeg);
  cfg.Set("J1J2flexion", 70 * kDeg);
  cfg.Set("K1K2flexion", 70 * kDeg);
  cfg.Set("CA1extension", -150 * kDeg);
  cfg.Set("CB1extension", -150 * kDeg);
  const YeadonHuman posed_human = YeadonHuman::Make(Male1(), {}, cfg);
  const BodyMesh posed = MakeBodyMesh(posed_human, MakeAthleteBodyFromYeadon(posed_human));
  ASSERT_EQ(posed.vertices_H.cols(), skinned.cols());
  double worst = 0;
  for (Eigen::Index i = 0; i < skinned.cols(); ++i) {
    if (mesh.skin_segment(1, i) >= 0) continue;
    worst = std::max(worst, (skinned.col(i) - posed.vertices_H.col(i)).norm());
  }
  EXPECT_LT(worst, 1e-12);  // metres; both are the same rigid motion computed two ways
}

TEST(BodyMesh, EquivalentEllipsoidsCarryTheDeLevaMassProperties) {
  const AthleteBody body = MakeDeLevaBody(1.75, 65, Sex::kFemale);
  const BodyMesh mesh = MakeEllipsoidBodyMesh(body);
  std::string why;
  EXPECT_TRUE(IsWatertight(mesh, &why)) << why;
  const std::vector<InertialProperties> parts = CalcMeshPartInertia(mesh);
  ASSERT_EQ(parts.size(), 15u);
  for (size_t g = 0; g < 15; ++g) {
    const InertialProperties& a = body.segments[g].in_H;
    EXPECT_NEAR(parts[g].mass_kg / a.mass_kg, 1.0, 0.005) << g;
    // A centrally symmetric polyhedron's centroid is its centre: exact up to rounding (metres).
    EXPECT_LT((parts[g].p_HoCm_H - a.p_HoCm_H).norm(), 1e-12) << g;
    EXPECT_LT((parts[g].I_Cm_H - a.I_Cm_H).norm() / a.I_Cm_H.norm(), 0.005) << g;
  }
}

TEST(BodyMesh, ExportsObjAndPlyAtomically) {
  const AthleteBody body = MakeDeLevaBody(1.75, 65, Sex::kMale);
  BodyMeshOptions options;
  options.points_per_semicircle = 6;
  options.ellipsoid_bands = 4;
  const BodyMesh mesh = MakeEllipsoidBodyMesh(body, options);
  const auto dir = acro::testing::TempDir();
  WriteBodyMesh(mesh, dir / "body.obj");
  WriteBodyMesh(mesh, dir / "body.ply");
  // Count the records written.
  std::ifstream obj(dir / "body.obj");
  int v = 0, f = 0, g = 0;
  for (std::string line; std::getline(obj, line);) {
    v += line.rfind("v ", 0) == 0;
    f += line.rfind("f ", 0) == 0;
    g += line.rfind("g ", 0) == 0;
  }
  EXPECT_EQ(v, mesh.num_vertices());
  EXPECT_EQ(f, mesh.num_triangles());
  EXPECT_EQ(g, 15);
  std::ifstream ply(dir / "body.ply");
  std::stringstream text;
  text << ply.rdbuf();
  EXPECT_NE(text.str().find("element vertex " + std::to_string(mesh.num_vertices())),
            std::string::npos);
  EXPECT_NE(text.str().find("element face " + std::to_string(mesh.num_triangles())),
            std::string::npos);
  EXPECT_THROW(WriteBodyMesh(mesh, dir / "body.stl"), InputError);
  // No temporary file is left beside the outputs.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    files += entry.path().filename().string().rfind("body.", 0) == 0;
  EXPECT_EQ(files, 2);
}

}  // namespace
}  // namespace acro::analysis
