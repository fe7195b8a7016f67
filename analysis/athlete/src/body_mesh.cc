#include "acro/athlete/body_mesh.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include "acro/base/demand.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"

namespace acro::analysis {

namespace {

constexpr double kPi = std::numbers::pi;

// OpenMesh triangle mesh with double-precision points.
struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// Collects parts (each a closed polyhedron) into the flat arrays of BodyMesh.
class MeshAssembler {
 public:
  explicit MeshAssembler(BodyMesh* mesh) : mesh_(mesh) {}

  // Adds one part: local vertices and triangles (indices into `vertices`), all in H.
  void AddPart(const std::vector<Eigen::Vector3d>& vertices,
               const std::vector<Eigen::Vector3i>& triangles,
               double density,
               int segment,
               const std::string& label) {
    // Build it with OpenMesh first: add_face refuses a non-manifold configuration.
    TriMesh part;
    std::vector<TriMesh::VertexHandle> handles;
    handles.reserve(vertices.size());
    for (const Eigen::Vector3d& v : vertices)
      handles.push_back(part.add_vertex(TriMesh::Point(v.x(), v.y(), v.z())));
    for (const Eigen::Vector3i& t : triangles) {
      const auto face = part.add_face(handles[static_cast<size_t>(t[0])],
                                      handles[static_cast<size_t>(t[1])],
                                      handles[static_cast<size_t>(t[2])]);
      ACRO_DEMAND(face.is_valid());
    }
    // Then copy it out of OpenMesh into the public arrays.
    const int part_index = static_cast<int>(mesh_->part_label.size());
    const int base = static_cast<int>(vertices_.size());
    for (auto vh : part.vertices()) {
      const TriMesh::Point& p = part.point(vh);
      vertices_.emplace_back(p[0], p[1], p[2]);
      vertex_segment_.push_back(segment);
    }
    for (auto fh : part.faces()) {
      Eigen::Vector3i tri;
      int k = 0;
      for (auto vh : part.fv_range(fh)) tri[k++] = base + vh.idx();
      triangles_.push_back(tri);
      mesh_->triangle_part.push_back(part_index);
    }
    mesh_->part_density_kg_m3.push_back(density);
    mesh_->part_segment.push_back(segment);
    mesh_->part_label.push_back(label);
  }

  void Finish() {
    mesh_->vertices_H.resize(3, static_cast<Eigen::Index>(vertices_.size()));
    for (size_t i = 0; i < vertices_.size(); ++i)
      mesh_->vertices_H.col(static_cast<Eigen::Index>(i)) = vertices_[i];
    mesh_->triangles.resize(3, static_cast<Eigen::Index>(triangles_.size()));
    for (size_t i = 0; i < triangles_.size(); ++i)
      mesh_->triangles.col(static_cast<Eigen::Index>(i)) = triangles_[i];
  }

  const std::vector<int>& vertex_segment() const { return vertex_segment_; }

 private:
  BodyMesh* mesh_;
  std::vector<Eigen::Vector3d> vertices_;
  std::vector<Eigen::Vector3i> triangles_;
  std::vector<int> vertex_segment_;
};

// A stadium cross-section as a closed polygon, counter-clockwise in its (u, v) plane (u the long
// axis): with `straight`, n+1 points on each half circle centred at (±t, 0) so that the straight
// sides are edges (2n+2 points; coincident pairs when t = 0); otherwise 2n points on a circle.
std::vector<Eigen::Vector2d> StadiumRing(double r, double t, int n, bool straight) {
  std::vector<Eigen::Vector2d> ring;
  if (straight) {
    for (int k = 0; k <= n; ++k) {
      const double a = -kPi / 2 + kPi * k / n;
      ring.emplace_back(t + r * std::cos(a), r * std::sin(a));
    }
    for (int k = 0; k <= n; ++k) {
      const double a = kPi / 2 + kPi * k / n;
      ring.emplace_back(-t + r * std::cos(a), r * std::sin(a));
    }
  } else {
    for (int k = 0; k < 2 * n; ++k) {
      const double a = 2 * kPi * k / (2 * n);
      ring.emplace_back(r * std::cos(a), r * std::sin(a));
    }
  }
  return ring;
}

// Joins consecutive rings (same size, counter-clockwise seen from +z, z increasing) with outward
// triangles; rings[i] are vertex indices.
void JoinRings(const std::vector<int>& lo,
               const std::vector<int>& hi,
               std::vector<Eigen::Vector3i>* tris) {
  const size_t m = lo.size();
  for (size_t k = 0; k < m; ++k) {
    const size_t j = (k + 1) % m;
    tris->emplace_back(lo[k], lo[j], hi[j]);
    tris->emplace_back(lo[k], hi[j], hi[k]);
  }
}

// Fan from `centre` over a ring; `up` for a cap facing +z.
void Cap(int centre, const std::vector<int>& ring, bool up, std::vector<Eigen::Vector3i>* tris) {
  const size_t m = ring.size();
  for (size_t k = 0; k < m; ++k) {
    const size_t j = (k + 1) % m;
    if (up) {
      tris->emplace_back(centre, ring[k], ring[j]);
    } else {
      tris->emplace_back(centre, ring[j], ring[k]);
    }
  }
}

// The polyhedron of one Yeadon solid in its frame S (docs in body_mesh.h / yeadon_human.h).
void SolidPolyhedron(const YeadonSolid& s,
                     const BodyMeshOptions& options,
                     std::vector<Eigen::Vector3d>* v,
                     std::vector<Eigen::Vector3i>* tris) {
  const int n = options.points_per_semicircle;
  // (u, v) → S: the long axis u along S's y (medio-lateral) or x (antero-posterior); both maps
  // keep the counter-clockwise order seen from +z.
  auto to_S = [&](const Eigen::Vector2d& uv, double z) {
    return s.anteroposterior ? Eigen::Vector3d(uv.x(), uv.y(), z)
                             : Eigen::Vector3d(-uv.y(), uv.x(), z);
  };
  auto add_ring = [&](const std::vector<Eigen::Vector2d>& ring, double z) {
    std::vector<int> idx;
    for (const Eigen::Vector2d& uv : ring) {
      idx.push_back(static_cast<int>(v->size()));
      v->push_back(to_S(uv, z));
    }
    return idx;
  };
  if (s.semi_ellipsoid) {
    // Latitude rings from the base (φ = 0) towards the apex; the apex a single vertex.
    const int bands = options.ellipsoid_bands;
    std::vector<std::vector<int>> rings;
    for (int i = 0; i < bands; ++i) {
      const double phi = kPi / 2 * i / bands;
      rings.push_back(
          add_ring(StadiumRing(s.r0_m * std::cos(phi), 0.0, n, false), s.height_m * std::sin(phi)));
    }
    const int apex = static_cast<int>(v->size());
    v->emplace_back(0, 0, s.height_m);
    const int base = static_cast<int>(v->size());
    v->emplace_back(0, 0, 0);
    for (int i = 0; i + 1 < bands; ++i)
      JoinRings(rings[static_cast<size_t>(i)], rings[static_cast<size_t>(i + 1)], tris);
    Cap(apex, rings.back(), true, tris);
    Cap(base, rings.front(), false, tris);
    return;
  }
  const bool straight = s.t0_m > 0.0 || s.t1_m > 0.0;
  const std::vector<int> lo = add_ring(StadiumRing(s.r0_m, s.t0_m, n, straight), 0.0);
  const std::vector<int> hi = add_ring(StadiumRing(s.r1_m, s.t1_m, n, straight), s.height_m);
  const int c0 = static_cast<int>(v->size());
  v->emplace_back(0, 0, 0);
  const int c1 = static_cast<int>(v->size());
  v->emplace_back(0, 0, s.height_m);
  JoinRings(lo, hi, tris);
  Cap(c0, lo, false, tris);
  Cap(c1, hi, true, tris);
}

// Skinning weights: a vertex of segment g within `blend` of g's proximal joint (measured along
// g's axis) shares its weight with g's parent, linearly from ½/½ at the joint to 1/0 at `blend`.
void SetSkinWeights(BodyMesh* mesh,
                    const std::vector<int>& vertex_segment,
                    const AthleteBody& body,
                    double blend) {
  const Eigen::Index nv = mesh->vertices_H.cols();
  mesh->skin_segment.resize(2, nv);
  mesh->skin_weight.resize(2, nv);
  for (Eigen::Index i = 0; i < nv; ++i) {
    const int g = vertex_segment[static_cast<size_t>(i)];
    const BodySegment& seg = body.segments[static_cast<size_t>(g)];
    mesh->skin_segment.col(i) << g, -1;
    mesh->skin_weight.col(i) << 1.0, 0.0;
    if (seg.parent < 0 || blend <= 0.0) continue;
    const Eigen::Vector3d axis = seg.p_HoE_H - seg.p_HoJ_H;
    const double length = axis.norm();
    if (length <= 0.0) continue;
    const double d = (mesh->vertices_H.col(i) - seg.p_HoJ_H).dot(axis / length);
    if (d >= blend) continue;
    const double w = std::clamp(0.5 + 0.5 * d / blend, 0.0, 1.0);
    mesh->skin_segment.col(i) << g, seg.parent;
    mesh->skin_weight.col(i) << w, 1.0 - w;
  }
}

void RequireValid(const BodyMeshOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError("", "body mesh options", why);
}

}  // namespace

bool BodyMeshOptions::IsValid(std::string* why) const {
  if (points_per_semicircle < 2) {
    *why = "points_per_semicircle must be at least 2";
    return false;
  }
  if (ellipsoid_bands < 2) {
    *why = "ellipsoid_bands must be at least 2";
    return false;
  }
  if (!(skin_blend_m >= 0.0)) {
    *why = "skin_blend_m must not be negative";
    return false;
  }
  return true;
}

BodyMesh MakeBodyMesh(const YeadonHuman& human,
                      const AthleteBody& body,
                      const BodyMeshOptions& options) {
  RequireValid(options);
  BodyMesh mesh;
  for (std::string_view name : kStandardSegmentNames) mesh.segment_names.emplace_back(name);
  MeshAssembler assembler(&mesh);
  // One closed polyhedron per solid, built in S and placed in H.
  for (const YeadonSolid& s : human.solids()) {
    std::vector<Eigen::Vector3d> v;
    std::vector<Eigen::Vector3i> tris;
    SolidPolyhedron(s, options, &v, &tris);
    for (Eigen::Vector3d& p : v) p = s.p_HoSo_H + s.R_HS * p;
    const int segment = StandardSegmentOfYeadonSolid(s.label);
    ACRO_DEMAND(segment >= 0);
    assembler.AddPart(v, tris, s.density_kg_m3, segment, s.label);
  }
  assembler.Finish();
  SetSkinWeights(&mesh, assembler.vertex_segment(), body, options.skin_blend_m);
  return mesh;
}

BodyMesh MakeEllipsoidBodyMesh(const AthleteBody& body, const BodyMeshOptions& options) {
  RequireValid(options);
  BodyMesh mesh;
  for (std::string_view name : kStandardSegmentNames) mesh.segment_names.emplace_back(name);
  MeshAssembler assembler(&mesh);
  const int n = options.points_per_semicircle;
  const int bands = options.ellipsoid_bands;
  for (size_t g = 0; g < body.segments.size(); ++g) {
    const InertialProperties& in = body.segments[g].in_H;
    // Principal axes and the uniform ellipsoid with these moments: I1 = m (b² + c²)/5, …, so
    // a² = 5 (I2 + I3 − I1) / (2m), and the density is m / (4/3 π a b c).
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(in.I_Cm_H);
    Eigen::Matrix3d V = eig.eigenvectors();
    if (V.determinant() < 0) V.col(2) *= -1.0;
    const Eigen::Vector3d I = eig.eigenvalues();
    Eigen::Vector3d semi;
    for (int k = 0; k < 3; ++k) {
      const double sq = 5.0 * (I.sum() - 2.0 * I[k]) / (2.0 * in.mass_kg);
      semi[k] = std::sqrt(std::max(sq, 1e-8));
    }
    const double density = in.mass_kg / (4.0 / 3.0 * kPi * semi.prod());
    // A latitude–longitude sphere (2·bands bands pole to pole, 2n meridians) mapped onto the
    // ellipsoid.
    std::vector<Eigen::Vector3d> v;
    std::vector<Eigen::Vector3i> tris;
    std::vector<std::vector<int>> rings;
    for (int i = 1; i < 2 * bands; ++i) {
      const double phi = -kPi / 2 + kPi * i / (2 * bands);
      std::vector<int> ring;
      for (int k = 0; k < 2 * n; ++k) {
        const double a = 2 * kPi * k / (2 * n);
        ring.push_back(static_cast<int>(v.size()));
        v.emplace_back(std::cos(phi) * std::cos(a), std::cos(phi) * std::sin(a), std::sin(phi));
      }
      rings.push_back(ring);
    }
    const int south = static_cast<int>(v.size());
    v.emplace_back(0, 0, -1);
    const int north = static_cast<int>(v.size());
    v.emplace_back(0, 0, 1);
    for (size_t i = 0; i + 1 < rings.size(); ++i) JoinRings(rings[i], rings[i + 1], &tris);
    Cap(south, rings.front(), false, &tris);
    Cap(north, rings.back(), true, &tris);
    for (Eigen::Vector3d& p : v) p = in.p_HoCm_H + V * semi.cwiseProduct(p);
    assembler.AddPart(v, tris, density, static_cast<int>(g), body.segments[g].name);
  }
  assembler.Finish();
  SetSkinWeights(&mesh, assembler.vertex_segment(), body, options.skin_blend_m);
  return mesh;
}

bool IsWatertight(const BodyMesh& mesh, std::string* why) {
  // Rebuild each part as an OpenMesh mesh and check it is a closed 2-manifold of genus 0.
  const size_t parts = mesh.part_label.size();
  std::vector<std::vector<int>> part_triangles(parts);
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t)
    part_triangles[static_cast<size_t>(mesh.triangle_part[static_cast<size_t>(t)])].push_back(
        static_cast<int>(t));
  for (size_t p = 0; p < parts; ++p) {
    TriMesh part;
    std::map<int, TriMesh::VertexHandle> handle;
    for (int t : part_triangles[p]) {
      std::array<TriMesh::VertexHandle, 3> f;
      for (int k = 0; k < 3; ++k) {
        const int vi = mesh.triangles(k, t);
        auto it = handle.find(vi);
        if (it == handle.end()) {
          const auto& x = mesh.vertices_H.col(vi);
          it = handle.emplace(vi, part.add_vertex(TriMesh::Point(x.x(), x.y(), x.z()))).first;
        }
        f[static_cast<size_t>(k)] = it->second;
      }
      if (!part.add_face(f[0], f[1], f[2]).is_valid()) {
        *why = "part " + mesh.part_label[p] + ": non-manifold triangle " + std::to_string(t);
        return false;
      }
    }
    for (auto eh : part.edges()) {
      if (part.is_boundary(eh)) {
        *why = "part " + mesh.part_label[p] + ": open edge";
        return false;
      }
    }
    const long euler = static_cast<long>(part.n_vertices()) - static_cast<long>(part.n_edges()) +
                       static_cast<long>(part.n_faces());
    if (euler != 2) {
      *why = "part " + mesh.part_label[p] + ": Euler characteristic " + std::to_string(euler) +
             " (expected 2)";
      return false;
    }
  }
  return true;
}

std::vector<InertialProperties> CalcMeshPartInertia(const BodyMesh& mesh) {
  // Divergence theorem over the tetrahedra (ref, a, b, c) of each triangle, relative to a point
  // of the part (less cancellation): with D = a·(b×c), volume Σ D/6, first moment Σ D (a+b+c)/24,
  // second moment Σ D (aaᵀ + bbᵀ + ccᵀ + ssᵀ)/120 with s = a+b+c (Tonon 2004, J. Math. Stat.
  // 1(1):8–11, the canonical tetrahedron's covariance).
  const size_t parts = mesh.part_label.size();
  std::vector<double> volume(parts, 0.0);
  std::vector<Eigen::Vector3d> first(parts, Eigen::Vector3d::Zero());
  std::vector<Eigen::Matrix3d> second(parts, Eigen::Matrix3d::Zero());
  std::vector<Eigen::Vector3d> ref(parts, Eigen::Vector3d::Zero());
  std::vector<bool> has_ref(parts, false);
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    const size_t p = static_cast<size_t>(mesh.triangle_part[static_cast<size_t>(t)]);
    if (!has_ref[p]) {
      ref[p] = mesh.vertices_H.col(mesh.triangles(0, t));
      has_ref[p] = true;
    }
    const Eigen::Vector3d a = mesh.vertices_H.col(mesh.triangles(0, t)) - ref[p];
    const Eigen::Vector3d b = mesh.vertices_H.col(mesh.triangles(1, t)) - ref[p];
    const Eigen::Vector3d c = mesh.vertices_H.col(mesh.triangles(2, t)) - ref[p];
    const double D = a.dot(b.cross(c));
    const Eigen::Vector3d s = a + b + c;
    volume[p] += D;
    first[p] += D * s;
    second[p] +=
        D * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  std::vector<InertialProperties> out(parts);
  for (size_t p = 0; p < parts; ++p) {
    const double V = volume[p] / 6.0;
    const double rho = mesh.part_density_kg_m3[p];
    if (V == 0.0) continue;
    const Eigen::Vector3d c = first[p] / 24.0 / V;  // centroid relative to ref
    const Eigen::Matrix3d C = rho * second[p] / 120.0;
    InertialProperties& in = out[p];
    in.mass_kg = rho * V;
    in.p_HoCm_H = ref[p] + c;
    // Inertia about ref from the covariance, then to the centroid (parallel-axis theorem).
    const Eigen::Matrix3d I_ref = C.trace() * Eigen::Matrix3d::Identity() - C;
    in.I_Cm_H =
        I_ref - in.mass_kg * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  }
  return out;
}

Eigen::Matrix3Xd CalcSkinnedVertices(const BodyMesh& mesh,
                                     const AthleteBody& rest,
                                     const AthleteBody& posed) {
  ACRO_DEMAND(rest.segments.size() == posed.segments.size());
  Eigen::Matrix3Xd out(3, mesh.vertices_H.cols());
  for (Eigen::Index i = 0; i < mesh.vertices_H.cols(); ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < 2; ++k) {
      const int g = mesh.skin_segment(k, i);
      const double w = mesh.skin_weight(k, i);
      if (g < 0 || w == 0.0) continue;
      const BodySegment& r = rest.segments[static_cast<size_t>(g)];
      const BodySegment& q = posed.segments[static_cast<size_t>(g)];
      const Eigen::Matrix3d R = q.R_pose * r.R_pose.transpose();
      sum += w * (q.p_HoJ_H + R * (mesh.vertices_H.col(i) - r.p_HoJ_H));
    }
    out.col(i) = sum;
  }
  return out;
}

void WriteBodyMesh(const BodyMesh& mesh, const std::filesystem::path& path) {
  const std::string ext = LowerExtension(path);
  std::string text;
  if (ext == "obj") {
    // Vertices, then one group of triangles per standard segment (1-based indices).
    text += "# Acrolab body mesh: " + std::to_string(mesh.num_vertices()) + " vertices, " +
            std::to_string(mesh.num_triangles()) + " triangles, metres, x anterior, y left, z up\n";
    for (Eigen::Index i = 0; i < mesh.vertices_H.cols(); ++i) {
      text += fmt::format("v {:.9g} {:.9g} {:.9g}\n",
                          mesh.vertices_H(0, i),
                          mesh.vertices_H(1, i),
                          mesh.vertices_H(2, i));
    }
    for (size_t g = 0; g < mesh.segment_names.size(); ++g) {
      text += "g " + mesh.segment_names[g] + "\n";
      for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
        if (mesh.part_segment[static_cast<size_t>(mesh.triangle_part[static_cast<size_t>(t)])] !=
            static_cast<int>(g))
          continue;
        text += fmt::format("f {} {} {}\n",
                            mesh.triangles(0, t) + 1,
                            mesh.triangles(1, t) + 1,
                            mesh.triangles(2, t) + 1);
      }
    }
  } else if (ext == "ply") {
    // ASCII PLY with the dominant skinning segment per vertex.
    text += "ply\nformat ascii 1.0\ncomment Acrolab body mesh, metres, x anterior, y left, z up\n";
    text += "element vertex " + std::to_string(mesh.num_vertices()) + "\n";
    text += "property double x\nproperty double y\nproperty double z\nproperty uchar segment\n";
    text += "element face " + std::to_string(mesh.num_triangles()) + "\n";
    text += "property list uchar int vertex_indices\nend_header\n";
    for (Eigen::Index i = 0; i < mesh.vertices_H.cols(); ++i) {
      const int g = mesh.skin_weight(0, i) >= mesh.skin_weight(1, i) ? mesh.skin_segment(0, i)
                                                                     : mesh.skin_segment(1, i);
      text += fmt::format("{:.9g} {:.9g} {:.9g} {}\n",
                          mesh.vertices_H(0, i),
                          mesh.vertices_H(1, i),
                          mesh.vertices_H(2, i),
                          g);
    }
    for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
      text += fmt::format(
          "3 {} {} {}\n", mesh.triangles(0, t), mesh.triangles(1, t), mesh.triangles(2, t));
    }
  } else {
    throw InputError(
        path.string(), "extension", "'" + ext + "' is not a mesh format (use .obj or .ply)");
  }
  WriteFileAtomically(path, text);
}

}  // namespace acro::analysis
