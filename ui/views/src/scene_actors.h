#pragma once

// The actors of a trial scene (internal to ui/views): the athlete's mesh, its ghost, skeleton,
// joints, centre of mass, its path and the residual arrow, or the keypoint links, and the markers;
// built once from a scene frame and updated in place — the overlay's and the free view's.

#include "acro/scene/place_scene.h"
#include "acro/scene/trial_scene.h"
#include "acro/views/scene_renderer.h"

namespace acro::ui::internal {

// The trampoline in the 3D views' colours: the black bed, the blue frame and pads, grey springs
// and legs.
inline void AddTrampoline(SceneRenderer* renderer, const analysis::TrampolineScene& trampoline) {
  analysis::SceneMesh bed = trampoline.bed;
  bed.colour = {0.1f, 0.1f, 0.12f, 1};
  renderer->AddMesh(bed);
  analysis::SceneMesh frame = trampoline.frame;
  frame.colour = {0.15f, 0.35f, 0.75f, 1};
  renderer->AddMesh(frame);
  for (analysis::SceneLines lines : {trampoline.springs, trampoline.legs}) {
    lines.colour = {0.55f, 0.55f, 0.58f, 1};
    lines.width_px = 2;
    renderer->AddLines(lines);
  }
}

struct Show : analysis::SceneShow {
  bool shaded = true;
};

class SceneActors {
 public:
  SceneActors(SceneRenderer* renderer,
              const analysis::TrialFrame& f,
              const Show& show,
              bool athlete,
              double scale_px)
      : renderer_(renderer), show_(show), athlete_(athlete) {
    analysis::SceneLines links = f.keypoint_links;
    links.width_px = 0.6 * scale_px;
    if (athlete_) {
      analysis::SceneMesh mesh = f.athlete.mesh;
      mesh.colour = {0.25f, 0.6f, 1.0f, 0.55f};  // the virtual athlete: blue, see-through
      mesh_ = renderer->AddMesh(mesh);
      // The ghost: the same athlete's mesh, orange and see-through (shown in the flights it is in).
      analysis::SceneMesh ghost = f.athlete.mesh;
      ghost.colour = {1.0f, 0.55f, 0.1f, 0.5f};
      ghost_ = renderer->AddMesh(ghost);
      analysis::SceneLines bones = f.athlete.skeleton;
      bones.colour = {0.95f, 0.95f, 0.95f, 1.0f};  // the trunk; the left red, the right green
      bones.width_px = 0.6 * scale_px;
      bones_ = renderer->AddLines(bones);
      joints_ = renderer->AddPoints(f.athlete.skeleton.points_W, 0.03, {0.1f, 0.5f, 0.1f, 1});
      com_ = renderer->AddPoints(f.athlete.com_W, 0.06, {1.0f, 0.85f, 0.0f, 1});
      analysis::SceneLines trail = f.com_trail;
      trail.width_px = 0.4 * scale_px;
      trail_ = renderer->AddLines(trail);
      analysis::SceneLines residual = f.residual;
      residual.width_px = 0.6 * scale_px;
      residual_ = renderer->AddLines(residual);
    } else {
      links_ = renderer->AddLines(links);
    }
    // Markers are about 14 mm wide; video keypoints are drawn as joints.
    markers_ = renderer->AddPoints(f.markers_W, athlete_ ? 0.01 : 0.02, {1.0f, 0.3f, 0.9f, 1});
    if (!show.shaded) {
      for (const int id :
           {mesh_, ghost_, bones_, joints_, com_, trail_, residual_, links_, markers_})
        if (id >= 0) renderer->SetLit(id, false);
    }
    Update(f, true);
  }

  /// What to show from the next Update on.
  void SetShow(const Show& show) { show_ = show; }

  void Update(const analysis::TrialFrame& f, bool visible) {
    if (athlete_) {
      renderer_->UpdateMesh(mesh_, f.athlete.mesh.vertices_W);
      renderer_->UpdateLines(bones_, f.athlete.skeleton.points_W);
      renderer_->UpdatePoints(joints_, f.athlete.skeleton.points_W);
      renderer_->UpdatePoints(com_, f.athlete.com_W);
      renderer_->UpdateLines(trail_, f.com_trail.points_W);
      renderer_->UpdateLines(residual_, f.residual.points_W);
      renderer_->SetVisible(mesh_, visible && show_.mesh);
      if (f.ghost_shown) renderer_->UpdateMesh(ghost_, f.ghost.mesh.vertices_W);
      renderer_->SetVisible(ghost_, visible && f.ghost_shown);
      renderer_->SetVisible(bones_, visible && show_.skeleton);
      renderer_->SetVisible(joints_, visible && show_.skeleton);
      renderer_->SetVisible(com_, visible && show_.com);
      renderer_->SetVisible(trail_, visible && show_.com && f.com_trail.num_segments() > 0);
      renderer_->SetVisible(residual_, visible && show_.residual);
    } else {
      renderer_->UpdateLines(links_, f.keypoint_links.points_W);
      renderer_->SetVisible(links_, visible && show_.skeleton);
    }
    renderer_->UpdatePoints(markers_, f.markers_W);
    renderer_->SetVisible(markers_, visible && show_.markers && f.markers_W.cols() > 0);
  }

 private:
  SceneRenderer* renderer_;
  Show show_;
  bool athlete_;
  int mesh_ = -1, ghost_ = -1, bones_ = -1, joints_ = -1, com_ = -1, trail_ = -1, residual_ = -1,
      links_ = -1, markers_ = -1;
};

}  // namespace acro::ui::internal
