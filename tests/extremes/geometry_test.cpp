// Cameras and geometry at the extremes (docs/reliability.md, "Extremes"): the camera in the plane
// of a face, inside an object and at the near plane; degenerate and sliver triangles; coincident
// and nearly coincident surfaces; lights on surfaces; sample budgets of 0 and 1.
#include <algorithm>
#include <cmath>

#include "area_lights.h"
#include "extremes.h"
#include "scene/topology.h"
#include "shade/render_image.h"

namespace epi::extremes {
namespace {

size_t count_pixels(const RgbImage& image, const std::function<bool(const float*)>& pred) {
  size_t n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += pred(image.at(x, y));
  return n;
}

bool reddish(const float* p) { return p[0] > 0.02f && p[0] > 2.0f * p[1]; }
bool greyish(const float* p) { return p[0] > 0.02f && std::abs(p[0] - p[1]) < 0.2f * p[0] && std::abs(p[1] - p[2]) < 0.2f * p[1]; }

// The ground (z = 0) seen exactly edge-on: it covers no pixel, the box stands above the horizon.
TEST(CameraExtremes, InThePlaneOfTheGround) {
  const Scene scene = plane_and_box();
  const Rendered run = render_frames(scene, moving(look({6.0f, -5.0f, 0.0f}, {0.0f, 0.0f, 0.0f}), {0.0f, 0.2f, 0.0f}, 6),
                                settings(64, 48));
  EXPECT_EQ(run.insane, 0u);
  const size_t red = count_pixels(run.image, reddish);
  EXPECT_GT(red, 80u);  // the box above the horizon (112 pixels when written)
  // Below the horizon (the camera's row 24 and down) the ground's edge-on plane shows nothing.
  size_t below = 0;
  for (int y = 26; y < 48; ++y)
    for (int x = 0; x < 64; ++x) below += run.image.at(x, y)[0] + run.image.at(x, y)[1] > 0.01f;
  EXPECT_EQ(below, 0u);
}

// The eye in the plane of the box's front face (y = -0.8): that face is edge-on.
TEST(CameraExtremes, InThePlaneOfAFace) {
  const Scene scene = plane_and_box();
  const Rendered run = render_frames(scene, moving(look({4.0f, -0.8f, 1.0f}, {0.0f, -0.8f, 0.6f}), {0.0f, 0.0f, 0.05f}, 6),
                                settings(64, 48));
  EXPECT_EQ(run.insane, 0u);
  EXPECT_GT(count_pixels(run.image, reddish), 40u);  // the box beside the edge-on face (66 when written)
  EXPECT_GT(count_pixels(run.image, greyish), 300u);
}

// Inside the closed box (faces outwards, light outside): every ray hits the inside of the box and
// no light leaks in, so the image is black; no edge or point is lost to NaN on the way.
TEST(CameraExtremes, InsideAClosedObjectNoLightLeaksIn) {
  const Scene scene = plane_and_box();
  std::vector<Camera> cameras;
  for (int k = 0; k < 8; ++k) {
    const float a = 0.3f * float(k);
    cameras.push_back(look({0.0f, 0.0f, 0.8f}, {std::cos(a), std::sin(a), 0.9f}, 60.0f));
  }
  const Rendered run = render_frames(scene, cameras, settings(48, 48));
  EXPECT_EQ(run.insane, 0u);
  const size_t lit = count_pixels(run.image, [](const float* p) { return p[0] + p[1] + p[2] > 0.01f; });
  EXPECT_EQ(lit, 0u);
  EXPECT_GT(run.stats.points.drawn, 48u * 48u / 2);  // the box's inside, densely cached
}

// A face at the near plane: just beyond it (1.001 x znear) it fills the image; just inside it
// (0.999 x znear) it is clipped and the camera sees the box's unlit inside; exactly at it, either,
// pixel by pixel, but always finite. Then the eye closer to the box's corner than the near distance:
// the box's edges cross the near plane and are clipped.
TEST(CameraExtremes, AtTheNearPlane) {
  Scene scene = plane_and_box();
  for (const float factor : {1.001f, 1.0f, 0.999f}) {
    SCOPED_TRACE(factor);
    Camera c = look({0.8f + 0.5f * factor, 0.0f, 0.8f}, {0.0f, 0.0f, 0.8f}, 60.0f);  // the box's +x face is x = 0.8
    c.znear = 0.5f;
    const Rendered run = render_frames(scene, {c, c, c, c}, settings(48, 48));
    EXPECT_EQ(run.insane, 0u);
    const size_t red = count_pixels(run.image, reddish);
    if (factor > 1.0f) {
      EXPECT_EQ(red, 48u * 48u);
    }
    if (factor < 1.0f) {
      EXPECT_EQ(red, 0u);
    }
  }
  // The eye inside the near distance of a box corner: the box's edges cross the near plane.
  std::vector<Camera> cameras;
  for (int k = 0; k < 8; ++k) {
    Camera n = look({0.85f + 0.01f * float(k), -0.85f, 1.65f}, {0.0f, 0.0f, 0.8f}, 70.0f);
    n.znear = 0.2f;
    cameras.push_back(n);
  }
  const Rendered run = render_frames(scene, cameras, settings(48, 48));
  EXPECT_EQ(run.insane, 0u);
  EXPECT_GT(count_pixels(run.image, greyish), 100u);  // the ground around the clipped corner
}

// Degenerate triangles (a repeated vertex, three collinear vertices, all three equal) added to the
// box. A Mesh holds none by contract (scene.h: "after repair"; io/gltf drops them with
// drop_degenerate_triangles): with them dropped, the edges are exactly those of the clean scene.
// Left in (a scene built in code that skips the repair), nothing breaks: finite pixels, the same
// image within 0.005, the same silhouettes; only their sides count as extra border edges (they lie
// on the box's own edges here, so the image does not change).
TEST(GeometryExtremes, DegenerateTrianglesChangeNothing) {
  const Scene clean = plane_and_box();
  Scene scene = clean;
  Mesh& box = scene.meshes[1];
  const uint32_t n = uint32_t(box.positions.size());
  box.positions.push_back({0.0f, 0.0f, 1.6f});    // n: top centre
  box.positions.push_back({0.8f, 0.8f, 0.8f});    // n+1: on the edge x = y = 0.8
  box.positions.push_back({0.8f, -0.8f, 0.8f});   // n+2: on the edge x = 0.8, y = -0.8
  box.triangles.push_back({n, n, n + 1});                   // repeated vertex
  box.triangles.push_back({1, 5, n + 2});                   // collinear: (0.8,-0.8,0) (0.8,-0.8,1.6) (0.8,-0.8,0.8)
  box.triangles.push_back({n + 1, n + 1, n + 1});           // a point
  box.triangles.push_back({3, 7, n + 1});                   // collinear along x = y = 0.8
  box.materials[0].triangle_count = uint32_t(box.triangles.size());
  const std::vector<Camera> cameras = moving(scene.cameras[0], {0.1f, 0.05f, 0.0f}, 8);
  const Rendered a = render_frames(clean, cameras, settings(64, 48));
  const Rendered raw = render_frames(scene, cameras, settings(64, 48));
  Scene repaired = scene;
  EXPECT_EQ(drop_degenerate_triangles(repaired.meshes[1]), 4u);
  const Rendered b = render_frames(repaired, cameras, settings(64, 48));
  for (const Rendered* r : {&raw, &b}) {
    EXPECT_EQ(r->insane, 0u);
    EXPECT_EQ(r->stats.edges.silhouette, a.stats.edges.silhouette);
    EXPECT_EQ(r->stats.edges.sharp, a.stats.edges.sharp);
    double diff = 0.0;
    for (size_t i = 0; i < a.image.pixels.size(); ++i) diff += std::abs(a.image.pixels[i] - r->image.pixels[i]);
    EXPECT_LT(diff / double(a.image.pixels.size()), 0.005);
  }
  EXPECT_EQ(b.stats.edges.border, a.stats.edges.border);
  EXPECT_EQ(b.image.pixels, a.image.pixels);  // repaired: the clean scene exactly
}

// The ground as a fan of 256 slivers (aspect ratio up to ~1000:1) instead of two triangles: the
// same image; the coplanar fan adds no sharp, border or silhouette edge inside the ground.
TEST(GeometryExtremes, SliverTrianglesRenderLikeTheSurfaceTheyTile) {
  const Scene clean = plane_and_box();
  Scene scene = clean;
  Mesh& ground = scene.meshes[0];
  ground.positions = {{-6, -6, 0}};
  for (int k = 0; k <= 128; ++k) ground.positions.push_back({6.0f, -6.0f + 12.0f * float(k) / 128.0f, 0.0f});
  for (int k = 1; k <= 128; ++k) ground.positions.push_back({6.0f - 12.0f * float(k) / 128.0f, 6.0f, 0.0f});
  ground.triangles.clear();
  for (uint32_t k = 1; k + 1 < ground.positions.size(); ++k) ground.triangles.push_back({0, k, k + 1});
  ground.materials[0].triangle_count = uint32_t(ground.triangles.size());
  const std::vector<Camera> cameras = moving(scene.cameras[0], {0.1f, 0.05f, 0.0f}, 8);
  const Rendered a = render_frames(clean, cameras, settings(64, 48));
  const Rendered b = render_frames(scene, cameras, settings(64, 48));
  EXPECT_EQ(b.insane, 0u);
  EXPECT_EQ(b.stats.edges.sharp, a.stats.edges.sharp);
  EXPECT_EQ(b.stats.edges.silhouette, a.stats.edges.silhouette);
  double diff = 0.0;
  for (size_t i = 0; i < a.image.pixels.size(); ++i) diff += std::abs(a.image.pixels[i] - b.image.pixels[i]);
  EXPECT_LT(diff / double(a.image.pixels.size()), 0.01);
}

// Two quads in the same plane, and two 1e-5 apart (scene size 12): the overlap shows one or the
// other, never a hole or self-shadowing acne (shadow rays of one surface hitting the other).
TEST(GeometryExtremes, CoincidentAndNearlyCoincidentSurfaces) {
  for (const float gap : {0.0f, 1e-5f}) {
    SCOPED_TRACE(gap);
    Scene scene;
    const uint32_t grey = add_material(scene, glm::vec3(0.6f));
    const uint32_t blue = add_material(scene, glm::vec3(0.1f, 0.2f, 0.8f));
    add_object(scene, quad_mesh({-6, -6, 0}, {12, 0, 0}, {0, 12, 0}, grey), "ground");
    add_object(scene, quad_mesh({-3, -3, gap}, {6, 0, 0}, {0, 6, 0}, blue), "overlay");
    scene.punctual_lights.push_back(point_light({1.0f, -2.0f, 8.0f}, glm::vec3(60.0f)));
    const std::vector<Camera> cameras = moving(look({0.0f, -7.0f, 6.0f}, {0.0f, 0.0f, 0.0f}), {0.1f, 0.0f, 0.0f}, 10);
    const Rendered run = render_frames(scene, cameras, settings(64, 64));
    EXPECT_EQ(run.insane, 0u);
    // Every pixel whose centre sees the overlay's inner part is lit like the grey or the blue
    // surface alone (luminance at least half the dimmer one's, from 1-spp ray traces of the scene
    // without either quad): no self-shadowing acne, no holes.
    Scene grey_only = scene, blue_only = scene;
    grey_only.objects.pop_back();
    blue_only.objects.erase(blue_only.objects.begin());
    View view;
    view.camera = cameras.back(), view.width = 64, view.height = 64;
    const RayScene grey_rs(grey_only), blue_rs(blue_only);
    const RgbImage grey_image = render_image(Shader(grey_rs, ShaderSettings{}), view, 1);
    const RgbImage blue_image = render_image(Shader(blue_rs, ShaderSettings{}), view, 1);
    const ViewFrame frame(view);
    size_t inner = 0, dark = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const Ray ray = frame.ray(float(x) + 0.5f, float(y) + 0.5f);
        const RayHit hit = grey_rs.intersect(ray);
        if (!hit.hit) continue;
        const glm::vec3 p = ray.origin + ray.direction * hit.t;
        if (std::max(std::abs(p.x), std::abs(p.y)) > 2.8f) continue;  // away from the overlay's border
        ++inner;
        const float floor = 0.5f * std::min(luminance(grey_image.at(x, y)), luminance(blue_image.at(x, y)));
        dark += luminance(run.image.at(x, y)) < floor;
      }
    EXPECT_GT(inner, 300u);
    EXPECT_EQ(dark, 0u);
  }
}

// A point light lying on the ground, and one on the box's top face: finite everywhere; the ground
// it lies in gets no light from it (grazing), the box's side facing it does.
TEST(LightExtremes, APointLightOnASurface) {
  for (const glm::vec3 position : {glm::vec3(2.0f, -3.0f, 0.0f), glm::vec3(0.0f, 0.0f, 1.6f)}) {
    SCOPED_TRACE(position.x);
    Scene scene = plane_and_box();
    scene.punctual_lights[0].position = position;
    const Rendered run = render_frames(scene, moving(scene.cameras[0], {0.1f, 0.05f, 0.0f}, 6), settings(64, 48));
    EXPECT_EQ(run.insane, 0u);
  }
  // The shader itself, at the very point where the light lies: a finite colour.
  Scene scene = plane_and_box();
  scene.punctual_lights[0].position = glm::vec3(2.0f, -3.0f, 0.0f);
  RayScene rs(scene);
  Shader shader(rs, ShaderSettings{});
  View view;
  view.camera = look({2.0f, -3.0f, 5.0f}, {2.0f, -3.0f, 0.0f}), view.camera.up = {0.0f, 1.0f, 0.0f};
  view.width = view.height = 16;
  ShadeBatch batch;
  const ShadeRequest centre{0, 8.0f, 8.0f};
  shader.shade(view, std::span(&centre, 1), batch);
  ASSERT_EQ(batch.results.size(), 1u);
  ASSERT_TRUE(batch.results[0].hit);
  EXPECT_LT(glm::length(batch.results[0].position - glm::vec3(2.0f, -3.0f, 0.0f)), 1e-5f);
  for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(batch.results[0].color[c])) << batch.results[0].color[c];
}

// An area light lying on the ground (coincident with it) and one standing on it (its lower edge on
// the ground), with soft-shadow edges on: finite images and edges.
TEST(LightExtremes, AnAreaLightOnASurface) {
  for (const bool standing : {false, true}) {
    SCOPED_TRACE(standing);
    Scene scene = plane_and_box();
    scene.punctual_lights.clear();
    const uint32_t emitter = add_material(scene, glm::vec3(0.0f), 0.0f, 1.0f, glm::vec3(4.0f));
    standing ? add_object(scene, quad_mesh({2, -2, 0}, {0, 0, 2}, {0, 2, 0}, emitter), "panel")
             : add_object(scene, quad_mesh({1.5f, -2, 0}, {2, 0, 0}, {0, 2, 0}, emitter), "panel");
    scene.area_lights = build_area_lights(scene);  // with outlines (soft-shadow edges), as the loader builds them
    render::FrameSettings s = settings(64, 48);
    s.soft_shadow_edges = true;
    ShaderSettings shading;
    shading.area_light_samples = 4;
    const Rendered run = render_frames(scene, moving(scene.cameras[0], {0.1f, 0.05f, 0.0f}, 8), s, shading);
    EXPECT_EQ(run.insane, 0u);
    EXPECT_GT(count_pixels(run.image, reddish), 50u);  // the box, lit by the panel
    size_t soft = 0;
    for (const edges::SceneEdge& e : run.edges) soft += e.kind == edges::EdgeKind::umbral || e.kind == edges::EdgeKind::penumbral;
    // Standing, the box casts a penumbra on the ground: soft-shadow edges found (and finite:
    // render_frames checks). Lying in the ground's plane, the light grazes the ground: none there.
    if (standing) {
      EXPECT_GT(soft, 0u);
    }
  }
}

TEST(BudgetExtremes, ABudgetOfZeroIsRefusedByName) {
  const Scene scene = plane_and_box();
  RayScene rs(scene);
  Shader shader(rs, ShaderSettings{});
  for (const double budget : {0.0, -0.1, 1.5, std::nan("")}) {
    render::FrameSettings s = settings(16, 16, budget);
    try {
      render::FrameRenderer renderer(scene, rs, shader, s);
      ADD_FAILURE() << "budget " << budget << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("sample budget"), std::string::npos) << e.what();
    }
  }
}

// A budget of 1 shades every pixel every frame: with the camera moving, each frame is a jittered
// one-sample ray trace reconstructed, within a small error of the pixel-centre ray trace.
TEST(BudgetExtremes, ABudgetOfOneShadesEveryPixelEveryFrame) {
  const Scene scene = plane_and_box();
  const std::vector<Camera> cameras = moving(scene.cameras[0], {0.2f, 0.1f, 0.0f}, 5);
  RayScene rs(scene);
  Shader shader(rs, ShaderSettings{});
  render::FrameSettings s = settings(64, 48, 1.0);
  s.sync = true;
  render::FrameRenderer renderer(scene, rs, shader, s);
  for (const Camera& c : cameras) {
    const RgbImage& image = renderer.render(c);
    EXPECT_EQ(count_insane(image, 50.0f, "budget 1"), 0u);
    EXPECT_EQ(renderer.stats().samples, size_t(64 * 48));
    View view;
    view.camera = c, view.width = 64, view.height = 48;
    const RgbImage traced = render_image(shader, view, 16);
    double diff = 0.0;
    for (size_t i = 0; i < image.pixels.size(); ++i) diff += std::abs(image.pixels[i] - traced.pixels[i]);
    EXPECT_LT(diff / double(image.pixels.size()), 0.02);
  }
}

}  // namespace
}  // namespace epi::extremes
