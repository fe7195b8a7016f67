#pragma once

// A triangulated body built from the same geometry as the inertia model: each of Yeadon's solids
// becomes a closed (watertight) polyhedron inscribed in it, with outward-facing triangles; mass
// properties follow from the mesh by exact polyhedral integration (divergence theorem), skinning
// weights bind vertices to the 15 standard segments for drawing a posed athlete, and the mesh
// exports to OBJ and PLY. For an athlete without measurements (de Leva route) each segment is drawn
// as its inertia-equivalent ellipsoid. OpenMesh stays inside analysis/src.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/athlete/athlete_body.h"
#include "acro/athlete/inertial_properties.h"
#include "acro/athlete/yeadon_human.h"

namespace acro::analysis {

struct BodyMeshOptions {
  /// Vertices per half circle of a stadium's round ends (a circle gets twice as many).
  int points_per_semicircle = 48;
  /// Latitude bands of the head's semi-ellipsoid (base to apex) and of each half of an equivalent
  /// ellipsoid.
  int ellipsoid_bands = 32;
  /// Vertices within this distance of a segment's proximal joint blend with the parent segment.
  double skin_blend_m = 0.04;

  bool IsValid(std::string* why) const;
};

struct BodyMesh {
  /// Vertex positions in H (the pose the mesh was made in).
  Eigen::Matrix3Xd vertices_H;
  /// Triangles as vertex indices, counter-clockwise seen from outside.
  Eigen::Matrix3Xi triangles;
  /// The closed part (a Yeadon solid, or an equivalent ellipsoid) of each triangle.
  std::vector<int> triangle_part;
  /// Per part: density (kg/m³), the standard segment it belongs to, and a label ("j5", "l_thigh").
  std::vector<double> part_density_kg_m3;
  std::vector<int> part_segment;
  std::vector<std::string> part_label;
  /// Skinning: up to two standard segments per vertex with weights summing to one (a second
  /// weight of 0 and segment −1 when the vertex follows one segment only).
  Eigen::Matrix2Xi skin_segment;
  Eigen::Matrix2Xd skin_weight;
  /// The 15 standard segment names.
  std::vector<std::string> segment_names;

  int num_vertices() const { return static_cast<int>(vertices_H.cols()); }
  int num_triangles() const { return static_cast<int>(triangles.cols()); }
};

/// The mesh of a Yeadon human, in its configuration. `body` (MakeAthleteBodyFromYeadon of the same
/// human) gives the joints used for skinning. Throws std::invalid_argument when `options` is not
/// valid.
BodyMesh MakeBodyMesh(const YeadonHuman& human,
                      const AthleteBody& body,
                      const BodyMeshOptions& options = {});

/// The mesh of any athlete body as inertia-equivalent ellipsoids: per segment the uniform
/// ellipsoid with the segment's mass, centre of mass and principal inertias (density 1000 kg/m³
/// unless that makes the inertia impossible, when the density is adjusted).
BodyMesh MakeEllipsoidBodyMesh(const AthleteBody& body, const BodyMeshOptions& options = {});

/// True when every part is a closed 2-manifold of genus 0 (checked with OpenMesh: no boundary
/// edge, V − E + F = 2 per part); else the first fault in *why.
bool IsWatertight(const BodyMesh& mesh, std::string* why);

/// Mass properties of every part by exact integration over its polyhedron (divergence theorem;
/// the canonical-tetrahedron covariance of Tonon 2004, equivalent to Mirtich 1996 and Eberly's
/// "Polyhedral Mass Properties"), in H.
std::vector<InertialProperties> CalcMeshPartInertia(const BodyMesh& mesh);

/// Vertex positions for a posed body by linear blend skinning: v' = Σ w_k (J'_k + R_k (v − J_k)),
/// J_k / J'_k the segment's joint in `rest` / `posed`, R_k = posed R_pose · rest R_poseᵀ.
Eigen::Matrix3Xd CalcSkinnedVertices(const BodyMesh& mesh,
                                     const AthleteBody& rest,
                                     const AthleteBody& posed);

/// Wavefront OBJ (one group per standard segment) or PLY (ASCII, with a per-vertex `segment`
/// property), chosen by the file extension (".obj" or ".ply"). Written to a temporary file and
/// renamed. Throws acro::InputError for another extension or when the file cannot be written.
void WriteBodyMesh(const BodyMesh& mesh, const std::filesystem::path& path);

}  // namespace acro::analysis
