#include "acro/views/scene_renderer.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkGlyph3DMapper.h>
#include <vtkMatrix4x4.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include <Eigen/Geometry>

namespace acro::ui {

namespace {

template <typename T>
vtkSmartPointer<T> New() {
  return vtkSmartPointer<T>::New();
}

// Copies 3 × N doubles (column-major: x y z per point, VTK's layout too) into VTK points.
void CopyPoints(const Eigen::Matrix3Xd& p, vtkPoints* points) {
  if (points->GetNumberOfPoints() != p.cols()) points->SetNumberOfPoints(p.cols());
  auto* data = static_cast<vtkDoubleArray*>(points->GetData());
  if (p.cols() > 0) std::memcpy(data->GetPointer(0), p.data(), sizeof(double) * 3 * p.cols());
  points->Modified();
}

vtkSmartPointer<vtkPoints> MakePoints(const Eigen::Matrix3Xd& p) {
  auto points = New<vtkPoints>();
  points->SetDataTypeToDouble();
  CopyPoints(p, points);
  return points;
}

void ApplyColour(vtkActor* actor, const analysis::Rgba& c) {
  actor->GetProperty()->SetColor(c.r, c.g, c.b);
  actor->GetProperty()->SetOpacity(c.a);
}

}  // namespace

Eigen::Matrix4d PinholeProjectionMatrix(const Eigen::Matrix3d& K,
                                        int width,
                                        int height,
                                        double near_m,
                                        double far_m) {
  // Eye coordinates e = diag(1, −1, −1) · (camera coordinates c): u·z_c = fx x_c + s y_c + cx z_c,
  // v·z_c = fy y_c + cy z_c, with z_c = −z_e = w_clip. OpenGL puts clip x/w at window
  // x = (x/w + 1) W / 2, which must be u + ½; window y (up) = (y/w + 1) H / 2 must be H − v − ½.
  // Solving for the rows (docs/overlay.md):
  const double W = width, H = height;
  const double fx = K(0, 0), s = K(0, 1), cx = K(0, 2), fy = K(1, 1), cy = K(1, 2);
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = 2 * fx / W;
  P(0, 1) = -2 * s / W;
  P(0, 2) = 1 - 2 * (cx + 0.5) / W;
  P(1, 1) = 2 * fy / H;
  P(1, 2) = 2 * (cy + 0.5) / H - 1;
  P(2, 2) = -(far_m + near_m) / (far_m - near_m);
  P(2, 3) = -2 * far_m * near_m / (far_m - near_m);
  P(3, 2) = -1;
  return P;
}

FreeViewpoint PresetViewpoint(ViewPreset preset, const Eigen::Vector3d& target_W, double distance_m) {
  FreeViewpoint view;
  view.target_W = target_W;
  switch (preset) {
    case ViewPreset::kSide:
      view.eye_W = target_W - distance_m * Eigen::Vector3d::UnitY();
      break;
    case ViewPreset::kFront:
      view.eye_W = target_W + distance_m * Eigen::Vector3d::UnitX();
      break;
    case ViewPreset::kTop:
      view.eye_W = target_W + distance_m * Eigen::Vector3d::UnitZ();
      view.up_W = Eigen::Vector3d::UnitY();
      break;
  }
  return view;
}

FreeViewpoint OrbitViewpoint(const FreeViewpoint& view, double azimuth_deg, double elevation_deg) {
  FreeViewpoint out = view;
  Eigen::Vector3d d = view.eye_W - view.target_W;
  d = Eigen::AngleAxisd(azimuth_deg * M_PI / 180, Eigen::Vector3d::UnitZ()) * d;
  const Eigen::Vector3d horizontal(d.x(), d.y(), 0);
  if (horizontal.norm() > 1e-9) {
    const Eigen::Vector3d axis = horizontal.cross(Eigen::Vector3d::UnitZ()).normalized();
    const double elevation = std::atan2(d.z(), horizontal.norm());
    const double limit = 89.0 * M_PI / 180;
    const double raised = std::clamp(elevation + elevation_deg * M_PI / 180, -limit, limit);
    d = Eigen::AngleAxisd(-(raised - elevation), axis) * d;
  }
  out.eye_W = view.target_W + d;
  return out;
}

struct SceneRenderer::Impl {
  struct Item {
    vtkSmartPointer<vtkActor> actor;
    vtkSmartPointer<vtkPolyData> data;
    vtkSmartPointer<vtkTextActor> text;
  };
  int width = 0;
  int height = 0;
  vtkSmartPointer<vtkRenderWindow> window;
  vtkSmartPointer<vtkRenderer> renderer;
  vtkSmartPointer<vtkUnsignedCharArray> pixels;
  std::vector<Item> items;

  Item& At(int id) {
    if (id < 0 || id >= static_cast<int>(items.size()))
      throw std::out_of_range("SceneRenderer: no actor " + std::to_string(id));
    return items[size_t(id)];
  }

  int AddPolyData(vtkSmartPointer<vtkPolyData> data, const analysis::Rgba& colour) {
    auto mapper = New<vtkPolyDataMapper>();
    mapper->SetInputData(data);
    mapper->ScalarVisibilityOff();
    auto actor = New<vtkActor>();
    actor->SetMapper(mapper);
    ApplyColour(actor, colour);
    renderer->AddActor(actor);
    items.push_back({actor, data, nullptr});
    return static_cast<int>(items.size()) - 1;
  }
};

SceneRenderer::SceneRenderer(int width, int height, int multisamples)
    : impl_(std::make_unique<Impl>()) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw std::invalid_argument("SceneRenderer: size " + std::to_string(width) + " x " +
                                std::to_string(height) + " px is not between 1 and 16384");
  impl_->width = width;
  impl_->height = height;
  impl_->window = New<vtkRenderWindow>();
  impl_->window->SetOffScreenRendering(1);
  impl_->window->SetAlphaBitPlanes(1);
  impl_->window->SetMultiSamples(multisamples);
  impl_->window->SetSize(width, height);
  impl_->renderer = New<vtkRenderer>();
  impl_->renderer->SetBackground(0, 0, 0);
  impl_->renderer->SetBackgroundAlpha(0);
  impl_->window->AddRenderer(impl_->renderer);
  impl_->pixels = New<vtkUnsignedCharArray>();
}

SceneRenderer::~SceneRenderer() = default;

int SceneRenderer::width() const { return impl_->width; }
int SceneRenderer::height() const { return impl_->height; }

int SceneRenderer::AddMesh(const analysis::SceneMesh& mesh) {
  auto data = New<vtkPolyData>();
  data->SetPoints(MakePoints(mesh.vertices_W));
  auto triangles = New<vtkCellArray>();
  triangles->AllocateExact(mesh.triangles.cols(), 3 * mesh.triangles.cols());
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    const vtkIdType ids[3] = {mesh.triangles(0, t), mesh.triangles(1, t), mesh.triangles(2, t)};
    triangles->InsertNextCell(3, ids);
  }
  data->SetPolys(triangles);
  return impl_->AddPolyData(data, mesh.colour);
}

void SceneRenderer::UpdateMesh(int id, const Eigen::Matrix3Xd& vertices_W) {
  Impl::Item& item = impl_->At(id);
  if (vertices_W.cols() != item.data->GetNumberOfPoints())
    throw std::invalid_argument("SceneRenderer::UpdateMesh: the vertex count changed");
  CopyPoints(vertices_W, item.data->GetPoints());
}

int SceneRenderer::AddLines(const analysis::SceneLines& lines) {
  auto data = New<vtkPolyData>();
  data->SetPoints(MakePoints(lines.points_W));
  auto cells = New<vtkCellArray>();
  cells->AllocateExact(lines.num_segments(), 2 * lines.num_segments());
  for (vtkIdType k = 0; k < lines.num_segments(); ++k) {
    const vtkIdType ids[2] = {2 * k, 2 * k + 1};
    cells->InsertNextCell(2, ids);
  }
  data->SetLines(cells);
  const int id = impl_->AddPolyData(data, lines.colour);
  vtkProperty* property = impl_->items[size_t(id)].actor->GetProperty();
  property->SetLineWidth(static_cast<float>(lines.width_px));
  property->SetRenderLinesAsTubes(true);
  return id;
}

void SceneRenderer::UpdateLines(int id, const Eigen::Matrix3Xd& points_W) {
  Impl::Item& item = impl_->At(id);
  if (points_W.cols() != item.data->GetNumberOfPoints())
    throw std::invalid_argument("SceneRenderer::UpdateLines: the segment count changed");
  CopyPoints(points_W, item.data->GetPoints());
}

int SceneRenderer::AddPoints(const Eigen::Matrix3Xd& points_W,
                             double radius_m,
                             analysis::Rgba colour) {
  auto data = New<vtkPolyData>();
  data->SetPoints(MakePoints(points_W));
  auto sphere = New<vtkSphereSource>();
  sphere->SetRadius(radius_m);
  sphere->SetThetaResolution(16);
  sphere->SetPhiResolution(12);
  auto mapper = New<vtkGlyph3DMapper>();
  mapper->SetInputData(data);
  mapper->SetSourceConnection(sphere->GetOutputPort());
  mapper->ScalingOff();
  mapper->OrientOff();
  mapper->ScalarVisibilityOff();
  auto actor = New<vtkActor>();
  actor->SetMapper(mapper);
  ApplyColour(actor, colour);
  impl_->renderer->AddActor(actor);
  impl_->items.push_back({actor, data, nullptr});
  return static_cast<int>(impl_->items.size()) - 1;
}

void SceneRenderer::UpdatePoints(int id, const Eigen::Matrix3Xd& points_W) {
  CopyPoints(points_W, impl_->At(id).data->GetPoints());
  impl_->At(id).data->Modified();
}

int SceneRenderer::AddText(const std::string& text, int size_px, analysis::Rgba colour) {
  auto actor = New<vtkTextActor>();
  actor->SetInput(text.c_str());
  vtkTextProperty* property = actor->GetTextProperty();
  property->SetFontSize(size_px);
  property->SetColor(colour.r, colour.g, colour.b);
  property->SetOpacity(colour.a);
  property->SetBackgroundColor(0, 0, 0);
  property->SetBackgroundOpacity(0.45);
  property->SetFontFamilyToCourier();
  actor->SetDisplayPosition(size_px / 2, impl_->height - size_px * 3 / 2 - size_px / 2);
  impl_->renderer->AddActor2D(actor);
  impl_->items.push_back({nullptr, nullptr, actor});
  return static_cast<int>(impl_->items.size()) - 1;
}

void SceneRenderer::UpdateText(int id, const std::string& text) {
  Impl::Item& item = impl_->At(id);
  if (!item.text) throw std::invalid_argument("SceneRenderer::UpdateText: not a text");
  item.text->SetInput(text.c_str());
}

void SceneRenderer::SetVisible(int id, bool visible) {
  Impl::Item& item = impl_->At(id);
  if (item.actor) item.actor->SetVisibility(visible);
  if (item.text) item.text->SetVisibility(visible);
}

void SceneRenderer::SetColour(int id, analysis::Rgba colour) {
  Impl::Item& item = impl_->At(id);
  if (item.actor) ApplyColour(item.actor, colour);
  if (item.text) item.text->GetTextProperty()->SetColor(colour.r, colour.g, colour.b);
}

void SceneRenderer::SetLit(int id, bool lit) {
  Impl::Item& item = impl_->At(id);
  if (item.actor) item.actor->GetProperty()->SetLighting(lit);
}

void SceneRenderer::SetBackground(analysis::Rgba colour) {
  impl_->renderer->SetBackground(colour.r, colour.g, colour.b);
  impl_->renderer->SetBackgroundAlpha(colour.a);
}

void SceneRenderer::LookThrough(const vision::Camera& pinhole) {
  if (pinhole.width_px != impl_->width || pinhole.height_px != impl_->height)
    throw std::invalid_argument("SceneRenderer::LookThrough: camera " + pinhole.name + " is " +
                                std::to_string(pinhole.width_px) + " x " +
                                std::to_string(pinhole.height_px) + " px, the view " +
                                std::to_string(impl_->width) + " x " +
                                std::to_string(impl_->height));
  // The view: eye at the camera centre, looking along its +z, up along its −y.
  const Eigen::Matrix3d R_WK = pinhole.R_KW.transpose();
  const Eigen::Vector3d centre = pinhole.CentreInWorld();
  const Eigen::Vector3d focal = centre + R_WK.col(2);
  const Eigen::Vector3d up = -R_WK.col(1);
  vtkCamera* camera = impl_->renderer->GetActiveCamera();
  camera->SetPosition(centre.data());
  camera->SetFocalPoint(focal.data());
  camera->SetViewUp(up.data());
  const Eigen::Matrix4d P =
      PinholeProjectionMatrix(pinhole.K, impl_->width, impl_->height, 0.05, 500.0);
  auto matrix = New<vtkMatrix4x4>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) matrix->SetElement(r, c, P(r, c));
  camera->SetExplicitProjectionTransformMatrix(matrix);
  camera->SetUseExplicitProjectionTransformMatrix(true);
}

void SceneRenderer::LookFrom(const FreeViewpoint& view) {
  vtkCamera* camera = impl_->renderer->GetActiveCamera();
  camera->SetUseExplicitProjectionTransformMatrix(false);
  camera->SetPosition(view.eye_W.data());
  camera->SetFocalPoint(view.target_W.data());
  camera->SetViewUp(view.up_W.data());
  camera->SetViewAngle(view.view_angle_deg);
  impl_->renderer->ResetCameraClippingRange();
}

void SceneRenderer::Render(RenderImage* out) {
  impl_->window->Render();
  const int W = impl_->width, H = impl_->height;
  impl_->window->GetRGBACharPixelData(0, 0, W - 1, H - 1, 0, impl_->pixels);
  out->width = W;
  out->height = H;
  out->rgba.resize(size_t(W) * size_t(H) * 4);
  // OpenGL's rows run bottom to top.
  const std::uint8_t* src = impl_->pixels->GetPointer(0);
  const size_t row = size_t(W) * 4;
  for (int y = 0; y < H; ++y)
    std::memcpy(out->rgba.data() + size_t(y) * row, src + size_t(H - 1 - y) * row, row);
}

}  // namespace acro::ui
