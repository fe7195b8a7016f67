#include "acro/views/scene_renderer.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkLight.h>
#include <vtkMatrix4x4.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>
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

void RenderTextLine(const std::string& text, int size_px, analysis::Rgba colour, RenderImage* out) {
  auto property = New<vtkTextProperty>();
  property->SetFontFamilyToCourier();
  property->SetFontSize(size_px);
  property->SetColor(colour.r, colour.g, colour.b);
  property->SetOpacity(colour.a);
  property->SetJustificationToLeft();
  property->SetVerticalJustificationToBottom();
  auto image = New<vtkImageData>();
  int dims[2] = {0, 0};
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  const bool drawn = renderer != nullptr && !text.empty() &&
                     renderer->RenderString(property, text, image, dims, 72);
  int extent[6] = {0, -1, 0, -1, 0, 0};
  if (drawn) image->GetExtent(extent);
  // FreeType's image may be padded (to powers of two): the text is the dims[0] × dims[1] pixels
  // at its bottom left, its rows `stride` pixels apart.
  const int stride = extent[1] - extent[0] + 1;
  const int tw = drawn ? std::min(dims[0], stride) : 0;
  const int th = drawn ? std::min(dims[1], extent[3] - extent[2] + 1) : 0;
  const int pad = std::max(2, size_px / 4);
  out->x0 = out->y0 = 0;
  out->width = tw + 2 * pad;
  out->height = std::max(th, size_px) + 2 * pad;
  // The box: black at half opacity (premultiplied).
  out->rgba.assign(size_t(out->width) * size_t(out->height) * 4, 0);
  for (size_t k = 3; k < out->rgba.size(); k += 4) out->rgba[k] = 128;
  if (!drawn || image->GetNumberOfScalarComponents() != 4) return;
  const auto* src = static_cast<const std::uint8_t*>(image->GetScalarPointer());
  for (int y = 0; y < th; ++y) {
    // VTK's image rows run bottom to top.
    const std::uint8_t* row = src + size_t(th - 1 - y) * size_t(stride) * 4;
    std::uint8_t* dst = out->rgba.data() + (size_t(y + pad) * size_t(out->width) + size_t(pad)) * 4;
    for (int x = 0; x < tw; ++x, row += 4, dst += 4) {
      const int a = row[3];
      if (a == 0) continue;
      // Text over the box: premultiplied colour + (1 − a) · box.
      for (int c = 0; c < 3; ++c) dst[c] = static_cast<std::uint8_t>((row[c] * a + 127) / 255);
      dst[3] = static_cast<std::uint8_t>(a + (dst[3] * (255 - a) + 127) / 255);
    }
  }
}

Eigen::Matrix4d PinholeProjectionMatrix(
    const Eigen::Matrix3d& K, int width, int height, double near_m, double far_m) {
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

FreeViewpoint PresetViewpoint(ViewPreset preset,
                              const Eigen::Vector3d& target_W,
                              double distance_m,
                              const Eigen::Vector3d& heading_W) {
  Eigen::Vector3d forward(heading_W.x(), heading_W.y(), 0.0);
  forward =
      forward.norm() > 1e-9 ? Eigen::Vector3d(forward.normalized()) : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward);
  FreeViewpoint view;
  view.target_W = target_W;
  switch (preset) {
    case ViewPreset::kSide:
      view.eye_W = target_W - distance_m * left;
      break;
    case ViewPreset::kFront:
      view.eye_W = target_W + distance_m * forward;
      break;
    case ViewPreset::kTop:
      view.eye_W = target_W + distance_m * Eigen::Vector3d::UnitZ();
      view.up_W = left;
      break;
  }
  return view;
}

FreeViewpoint FollowViewpoint(const FreeViewpoint& view, const Eigen::Vector3d& target_W) {
  FreeViewpoint out = view;
  out.eye_W = view.eye_W + (target_W - view.target_W);
  out.target_W = target_W;
  return out;
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
    d = Eigen::AngleAxisd(raised - elevation, axis) * d;  // about h × z: h turns up
  }
  out.eye_W = view.target_W + d;
  return out;
}

struct SceneRenderer::Impl {
  struct Item {
    vtkSmartPointer<vtkActor> actor;
    vtkSmartPointer<vtkPolyData> data;
    /// A set of spheres: their radius and how many the mesh holds (unused ones collapse to a
    /// point, drawing nothing).
    double radius_m = 0;
    Eigen::Index capacity = 0;
    Eigen::Matrix3Xd vertices;
  };
  int width = 0;
  int height = 0;
  vtkSmartPointer<vtkRenderWindow> window;
  vtkSmartPointer<vtkRenderer> renderer;
  vtkSmartPointer<vtkUnsignedCharArray> pixels = New<vtkUnsignedCharArray>();  // bottom row first
  std::vector<Item> items;
  /// Set by LookThrough: each render then projects exactly the region it renders.
  std::optional<Eigen::Matrix3d> K;

  /// The window's size now: the view's, or through a camera just enough for the region drawn.
  int window_width = 0;
  int window_height = 0;

  void Resize(int w, int h) {
    if (w == window_width && h == window_height) return;
    window->SetSize(w, h);
    window_width = w;
    window_height = h;
  }

  // Through a camera, renders only `r` (a part of the view) in a window just larger than it (sizes
  // in steps of 128 px, so that it is rarely resized): the projection is the camera's K shifted
  // so that r's top-left corner is the window's, and the pixels are the whole view's. Everything
  // VTK does per frame over the whole window (clear, resolve, blit) then costs the region's size,
  // not the view's. Returns the GL rectangle to read: (x, y) bottom-left, inclusive ends.
  std::array<int, 4> PrepareRegion(const PixelBox& r) {
    if (!K) {
      Resize(width, height);
      return {r.x0, height - r.y1, r.x1 - 1, height - 1 - r.y0};
    }
    const auto step = [](int n, int limit) { return std::min(limit, (n + 127) / 128 * 128); };
    Resize(step(r.width(), width), step(r.height(), height));
    Eigen::Matrix3d shifted = *K;
    shifted(0, 2) -= r.x0;
    shifted(1, 2) -= r.y0;
    const Eigen::Matrix4d P =
        PinholeProjectionMatrix(shifted, window_width, window_height, 0.05, 500.0);
    auto matrix = New<vtkMatrix4x4>();
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) matrix->SetElement(i, j, P(i, j));
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->SetExplicitProjectionTransformMatrix(matrix);
    camera->SetUseExplicitProjectionTransformMatrix(true);
    return {0, window_height - r.height(), r.width() - 1, window_height - 1};
  }

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
    Item item;
    item.actor = actor;
    item.data = data;
    items.push_back(std::move(item));
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
  impl_->Resize(width, height);
  impl_->renderer = New<vtkRenderer>();
  impl_->renderer->SetBackground(0, 0, 0);
  impl_->renderer->SetBackgroundAlpha(0);
  impl_->window->AddRenderer(impl_->renderer);
}

SceneRenderer::~SceneRenderer() = default;

int SceneRenderer::width() const {
  return impl_->width;
}
int SceneRenderer::height() const {
  return impl_->height;
}

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
  const int id = impl_->AddPolyData(data, mesh.colour);
  // Meshes are closed: their back faces are never seen (and a translucent body shows only its
  // front).
  impl_->items[size_t(id)].actor->GetProperty()->BackfaceCullingOn();
  return id;
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
  const bool sided =
      !lines.segment_sides.empty() && lines.segment_sides.size() == size_t(lines.num_segments());
  if (sided) {
    // Per segment its side's colour (cell scalars, taken as colours as they are).
    auto colours = New<vtkUnsignedCharArray>();
    colours->SetNumberOfComponents(4);
    colours->SetNumberOfTuples(lines.num_segments());
    for (vtkIdType k = 0; k < lines.num_segments(); ++k) {
      const analysis::Rgba c = analysis::SideColour(lines.segment_sides[size_t(k)], lines.colour);
      const auto byte = [](float x) { return static_cast<unsigned char>(std::lround(255 * x)); };
      colours->SetTypedTuple(
          k, std::array<unsigned char, 4>{byte(c.r), byte(c.g), byte(c.b), byte(c.a)}.data());
    }
    data->GetCellData()->SetScalars(colours);
  }
  const int id = impl_->AddPolyData(data, lines.colour);
  if (sided) {
    vtkMapper* mapper = impl_->items[size_t(id)].actor->GetMapper();
    mapper->ScalarVisibilityOn();
    mapper->SetScalarModeToUseCellData();
    mapper->SetColorModeToDirectScalars();
  }
  vtkProperty* property = impl_->items[size_t(id)].actor->GetProperty();
  property->SetLineWidth(static_cast<float>(lines.width_px));
  property->SetRenderLinesAsTubes(true);
  return id;
}

void SceneRenderer::UpdateLines(int id, const Eigen::Matrix3Xd& points_W) {
  Impl::Item& item = impl_->At(id);
  const Eigen::Index n = points_W.cols() / 2;
  if (2 * n != item.data->GetNumberOfPoints()) {
    // A new segment count (a trail that grows): new cells.
    auto cells = New<vtkCellArray>();
    cells->AllocateExact(n, 2 * n);
    for (vtkIdType k = 0; k < n; ++k) {
      const vtkIdType ids[2] = {2 * k, 2 * k + 1};
      cells->InsertNextCell(2, ids);
    }
    item.data->SetLines(cells);
    item.data->GetCellData()->SetScalars(nullptr);  // per-segment sides were for the old count
  }
  CopyPoints(points_W.leftCols(2 * n), item.data->GetPoints());
}

int SceneRenderer::AddPoints(const Eigen::Matrix3Xd& points_W,
                             double radius_m,
                             analysis::Rgba colour) {
  const int id = impl_->AddPolyData(New<vtkPolyData>(), colour);
  impl_->items[size_t(id)].radius_m = radius_m;
  UpdatePoints(id, points_W);
  return id;
}

void SceneRenderer::UpdatePoints(int id, const Eigen::Matrix3Xd& points_W) {
  // One mesh of all the spheres (a unit sphere of kRings × kSegments quads, scaled and moved):
  // VTK's glyph mapper costs about 0.3 ms per sphere per frame on Mesa's software rasteriser;
  // this costs its triangles (about 0.7 µs each there), kept few.
  static constexpr int kRings = 6, kSegments = 10;
  static constexpr int kVerts = (kRings + 1) * kSegments;
  static const Eigen::Matrix3Xd unit = [] {
    Eigen::Matrix3Xd u(3, kVerts);
    for (int i = 0; i <= kRings; ++i)
      for (int j = 0; j < kSegments; ++j) {
        const double th = M_PI * i / kRings, ph = 2 * M_PI * j / kSegments;
        u.col(i * kSegments + j) =
            Eigen::Vector3d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      }
    return u;
  }();
  Impl::Item& item = impl_->At(id);
  const Eigen::Index n = points_W.cols();
  if (n > item.capacity || item.capacity == 0) {
    // Grow: the triangles and the normals (the unit sphere's, per vertex) are set once per size.
    item.capacity = std::max<Eigen::Index>({n, 2 * item.capacity, 1});
    auto triangles = New<vtkCellArray>();
    auto normals = New<vtkFloatArray>();
    normals->SetNumberOfComponents(3);
    normals->SetNumberOfTuples(item.capacity * kVerts);
    for (Eigen::Index k = 0; k < item.capacity; ++k) {
      const vtkIdType base = k * kVerts;
      for (int v = 0; v < kVerts; ++v)
        normals->SetTuple3(base + v, unit(0, v), unit(1, v), unit(2, v));
      for (int i = 0; i < kRings; ++i)
        for (int j = 0; j < kSegments; ++j) {
          const vtkIdType a = base + i * kSegments + j,
                          b = base + i * kSegments + (j + 1) % kSegments;
          const vtkIdType t1[3] = {a, a + kSegments, b}, t2[3] = {b, a + kSegments, b + kSegments};
          triangles->InsertNextCell(3, t1);
          triangles->InsertNextCell(3, t2);
        }
    }
    item.vertices.resize(3, item.capacity * kVerts);
    item.data->SetPoints(MakePoints(item.vertices));
    item.data->SetPolys(triangles);
    item.data->GetPointData()->SetNormals(normals);
  }
  for (Eigen::Index k = 0; k < item.capacity; ++k) {
    auto block = item.vertices.middleCols(k * kVerts, kVerts);
    if (k < n) {
      block = (item.radius_m * unit).colwise() + points_W.col(k);
    } else {
      block.colwise() = n > 0 ? Eigen::Vector3d(points_W.col(0)) : Eigen::Vector3d::Zero();
    }
  }
  CopyPoints(item.vertices, item.data->GetPoints());
}

void SceneRenderer::SetVisible(int id, bool visible) {
  Impl::Item& item = impl_->At(id);
  if (item.actor) item.actor->SetVisibility(visible);
}

void SceneRenderer::SetColour(int id, analysis::Rgba colour) {
  Impl::Item& item = impl_->At(id);
  if (item.actor) ApplyColour(item.actor, colour);
}

void SceneRenderer::SetLit(int id, bool lit) {
  Impl::Item& item = impl_->At(id);
  if (item.actor) item.actor->GetProperty()->SetLighting(lit);
}

void SceneRenderer::SetSceneLights(const std::vector<Eigen::Vector3d>& directions_W,
                                   double intensity,
                                   double headlight_intensity) {
  vtkRenderer* renderer = impl_->renderer;
  renderer->AutomaticLightCreationOff();
  renderer->RemoveAllLights();
  for (const Eigen::Vector3d& d : directions_W) {
    auto light = New<vtkLight>();
    light->SetLightTypeToSceneLight();
    light->SetPositional(false);
    // A directional light shines from its position to its focal point.
    const Eigen::Vector3d from = -d.normalized();
    light->SetPosition(from.data());
    light->SetFocalPoint(0, 0, 0);
    light->SetIntensity(intensity);
    renderer->AddLight(light);
  }
  auto head = New<vtkLight>();
  head->SetLightTypeToHeadlight();
  head->SetIntensity(headlight_intensity);
  renderer->AddLight(head);
}

void SceneRenderer::SetBackground(analysis::Rgba colour) {
  impl_->renderer->SetBackground(colour.r, colour.g, colour.b);
  impl_->renderer->SetBackgroundAlpha(colour.a);
}

void SceneRenderer::LookThrough(const vision::Camera& pinhole) {
  if (pinhole.width_px != impl_->width || pinhole.height_px != impl_->height)
    throw std::invalid_argument(
        "SceneRenderer::LookThrough: camera " + pinhole.name + " is " +
        std::to_string(pinhole.width_px) + " x " + std::to_string(pinhole.height_px) +
        " px, the view " + std::to_string(impl_->width) + " x " + std::to_string(impl_->height));
  // The view: eye at the camera centre, looking along its +z, up along its −y.
  const Eigen::Matrix3d R_WK = pinhole.R_KW.transpose();
  const Eigen::Vector3d centre = pinhole.CentreInWorld();
  const Eigen::Vector3d focal = centre + R_WK.col(2);
  const Eigen::Vector3d up = -R_WK.col(1);
  vtkCamera* camera = impl_->renderer->GetActiveCamera();
  camera->SetPosition(centre.data());
  camera->SetFocalPoint(focal.data());
  camera->SetViewUp(up.data());
  impl_->K = pinhole.K;
}

void SceneRenderer::LookFrom(const FreeViewpoint& view) {
  impl_->K.reset();
  vtkCamera* camera = impl_->renderer->GetActiveCamera();
  camera->SetUseExplicitProjectionTransformMatrix(false);
  camera->SetPosition(view.eye_W.data());
  camera->SetFocalPoint(view.target_W.data());
  camera->SetViewUp(view.up_W.data());
  camera->SetViewAngle(view.view_angle_deg);
  camera->SetParallelProjection(view.parallel_scale_m > 0);
  if (view.parallel_scale_m > 0) camera->SetParallelScale(view.parallel_scale_m);
  impl_->renderer->ResetCameraClippingRange();
}

void SceneRenderer::Render(RenderImage* out) {
  Render(PixelBox{0, 0, impl_->width, impl_->height}, out);
}

void SceneRenderer::Render(const PixelBox& region, RenderImage* out) {
  const int W = impl_->width, H = impl_->height;
  const PixelBox r{std::clamp(region.x0, 0, W),
                   std::clamp(region.y0, 0, H),
                   std::clamp(region.x1, 0, W),
                   std::clamp(region.y1, 0, H)};
  out->x0 = r.x0;
  out->y0 = r.y0;
  out->width = std::max(0, r.width());
  out->height = std::max(0, r.height());
  out->rgba.resize(size_t(out->width) * size_t(out->height) * 4);
  if (r.empty()) return;
  const std::array<int, 4> gl = impl_->PrepareRegion(r);
  impl_->window->Render();
  // OpenGL's rows run bottom to top.
  impl_->window->GetRGBACharPixelData(gl[0], gl[1], gl[2], gl[3], 0, impl_->pixels);
  const std::uint8_t* src = impl_->pixels->GetPointer(0);
  const size_t row = size_t(out->width) * 4;
  for (int y = 0; y < out->height; ++y)
    std::memcpy(out->rgba.data() + size_t(y) * row, src + size_t(out->height - 1 - y) * row, row);
}

}  // namespace acro::ui
