#include "caustics.h"

#include <algorithm>
#include <cmath>

#include "caustix/formats/frame.h"
#include "caustix/formats/slicing.h"
#include "shader_text.h"

namespace caustix::runtime {
namespace {

constexpr float kEmptyV = -1.0e30f;  // position map value where there is no surface
constexpr std::uint32_t kTileTexels = 8;  // position-map texels per depth tile side
// Most primitives one map may list: 4 M ((volume, plane) pairs; 224 MB with
// their geometry).
constexpr std::uint64_t kMaxPrimitives = 4u << 20;
constexpr GLsizeiptr kPrimitiveBytes = 64;  // four vec4, caustics_geometry.comp

struct MapGpu {
  LevelMap* lm = nullptr;
  gl::Texture position_map;  // R32F at lm->map_size
  gl::Texture caustics;      // RGBA32F at caustics_size: irradiance on the plane and its direction (caustics_geometry.comp)
  gl::Framebuffer fbo;
  std::uint32_t caustics_size = 0;
  // Planes in use, and the options they were derived with.
  std::vector<ReferencePlane> planes;
  gl::Buffer planes_buffer;
  bool planes_valid = false;
  bool planes_smart = true;
  std::optional<std::uint32_t> planes_n;
  std::optional<float> planes_eps;
  float self_tolerance = 0;
  gl::Texture depth_tiles;  // RG32F min/max frame V per tile
  gl::Framebuffer position_fbo;  // run-time re-derivation
  gl::Texture position_depth;
  gl::Buffer list, primitives, command, rect_indices;
  std::uint64_t capacity = 0;   // entries the list (and the primitive buffer) may hold
  std::uint64_t allocated = 0;  // entries the buffers are allocated for
  // Volumetric baseline: receiver slices and illumination per plane.
  gl::Texture slices, illumination;
  std::uint32_t slice_count = 0, slice_size = 0;
  // Dispersion (a water that disperses, several wavelengths traced): the
  // sum over wavelengths and the RGB colour texture (caustics_accumulate).
  gl::Texture spectral_sum, color;
  std::uint32_t spectral_size = 0;
  bool spectral = false;  // the last update traced several wavelengths: `color` is valid
  std::uint64_t gpu_bytes = 0;
};

std::vector<ReferencePlane> planes_for(const LevelMap& lm, const CausticsOptions& o) {
  const bool smart = o.method == CausticsMethod::kLevelMap;
  if (!o.planes && !o.epsilon) return smart ? lm.smart_planes : lm.uniform_planes;
  const double h = 2.0 * lm.frame.half[1];
  if (!smart) {
    const std::uint32_t n = o.planes ? *o.planes
                                     : static_cast<std::uint32_t>(std::clamp(std::ceil(h / (2.0 * *o.epsilon)), 1.0, 4096.0));
    return uniform_planes(h, n);
  }
  const double eps = o.epsilon ? double{*o.epsilon} : h / (2.0 * *o.planes);
  return smart_planes(h, static_cast<std::uint32_t>(lm.histogram.size()), lm.sub_boxes, eps, nullptr);
}

glm::vec3 v3(const Vec3f& v) { return {v[0], v[1], v[2]}; }

void set_frame(const gl::Program& p, const BoundingFrame& f) {
  p.set("u_origin", glm::vec3(static_cast<float>(f.origin[0]), static_cast<float>(f.origin[1]), static_cast<float>(f.origin[2])));
  p.set("u_U", v3(f.u));
  p.set("u_V", v3(f.v));
  p.set("u_W", v3(f.w));
  p.set("u_half", v3(f.half));
}

}  // namespace

struct CausticsEngine::Impl {
  const WaterSurface* water = nullptr;
  std::vector<MapGpu> maps;
  gl::Program prepare, cull, fixup, geometry, levelmap, volumetric, slab, combine, presence, profile, accumulate;
  gl::Program splat_photon, splat_points;
  // Photon splatting (one set, reused map after map): the photon texture,
  // the vertex buffer it is copied into, and the points' vertex array.
  gl::Texture photon_texture;
  gl::Framebuffer photon_fbo;
  gl::Buffer photon_vbo;
  gl::VertexArray photon_vao;
  std::uint32_t photon_size = 0;
  gl::Buffer histogram;
  std::uint32_t histogram_levels = 0;
  gl::Buffer refracted, flux;
  gl::VertexArray empty_vao;
  std::function<void(std::uint32_t)> draw_object;
  std::function<glm::mat4(std::uint32_t)> model_of;
  CausticsStats stats;
  std::vector<std::size_t> drawn_maps;  // maps updated since reset_stats()

  // The plane set in use follows the method (smart or uniform) and the
  // run-time overrides; rebuilt only when one of them changes.
  void ensure_planes(MapGpu& m, const CausticsOptions& o) {
    const bool smart = o.method == CausticsMethod::kLevelMap;
    if (m.planes_valid && m.planes_smart == smart && m.planes_n == o.planes && m.planes_eps == o.epsilon) return;
    m.planes = planes_for(*m.lm, o);
    std::vector<float> packed;
    float widest = 0;
    for (const auto& p : m.planes) {
      packed.push_back(p.offset);
      packed.push_back(p.epsilon);
      widest = std::max(widest, p.epsilon);
    }
    m.planes_buffer = gl::make_buffer();
    if (packed.empty()) packed = {0.0f, 0.0f};  // GL refuses empty buffers; draw_map draws nothing then
    glNamedBufferStorage(m.planes_buffer.get(), static_cast<GLsizeiptr>(packed.size() * 4), packed.data(), 0);
    // A point further behind the first surface than any window (or two
    // depth quanta) is self-shadowed.
    m.self_tolerance = std::max(widest, static_cast<float>(4.0 * m.lm->frame.half[1] / kDepthQuantum));
    m.planes_valid = true;
    m.planes_smart = smart;
    m.planes_n = o.planes;
    m.planes_eps = o.epsilon;
  }

  void ensure_caustics_target(MapGpu& m, std::uint32_t size) {
    if (m.caustics_size == size && m.caustics.get()) return;
    // A mip chain, so that casting a fine caustics map onto a receiver seen
    // from afar averages it instead of aliasing (averaging keeps the mean
    // irradiance).
    GLsizei levels = 1;
    while ((size >> levels) > 0) ++levels;
    m.caustics = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(m.caustics.get(), levels, GL_RGBA32F, static_cast<GLsizei>(size), static_cast<GLsizei>(size));
    glTextureParameteri(m.caustics.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(m.caustics.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(m.caustics.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(m.caustics.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    m.fbo = gl::make_framebuffer();
    glNamedFramebufferTexture(m.fbo.get(), GL_COLOR_ATTACHMENT0, m.caustics.get(), 0);
    m.caustics_size = size;
  }

  void ensure_slices(MapGpu& m, std::uint32_t count, std::uint32_t size) {
    if (m.slice_count == count && m.slice_size == size && m.slices.get()) return;
    m.slices = gl::make_texture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(m.slices.get(), 1, GL_R8, static_cast<GLsizei>(size), static_cast<GLsizei>(size), static_cast<GLsizei>(count));
    m.illumination = gl::make_texture(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(m.illumination.get(), 1, GL_RGBA32F, static_cast<GLsizei>(size), static_cast<GLsizei>(size), static_cast<GLsizei>(count));
    m.slice_count = count;
    m.slice_size = size;
  }

  // Min/max frame V per tile of the position map (for per-plane culling),
  // by profile.comp: one code path at load and after re-derivation.
  void build_depth_tiles(MapGpu& m) {
    const std::uint32_t nt = (m.lm->map_size + kTileTexels - 1) / kTileTexels;
    if (!m.depth_tiles.get()) {
      m.depth_tiles = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(m.depth_tiles.get(), 1, GL_RG32F, static_cast<GLsizei>(nt), static_cast<GLsizei>(nt));
    }
    profile.use();
    profile.set("u_mode", 1);
    profile.set("u_tile", static_cast<int>(kTileTexels));
    glBindTextureUnit(0, m.position_map.get());
    glBindImageTexture(0, m.depth_tiles.get(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    glDispatchCompute((nt + 7) / 8, (nt + 7) / 8, 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
  }

  std::uint64_t bytes_of(const MapGpu& m) const {
    const std::uint64_t pm = std::uint64_t{m.lm->map_size} * m.lm->map_size * 4;
    const std::uint64_t cm = std::uint64_t{m.caustics_size} * m.caustics_size * 16 * 4 / 3;  // RGBA32F and its mips
    const std::uint64_t sl = std::uint64_t{m.slice_size} * m.slice_size * m.slice_count * (1 + 16);
    const std::uint64_t tiles = pm / (kTileTexels * kTileTexels) * 2;
    const std::uint64_t spectral = std::uint64_t{m.spectral_size} * m.spectral_size * 16 * (1 + 4 / 3.0);  // sum, colour and its mips
    return pm + cm + sl + tiles + spectral + m.planes.size() * 8 + m.allocated * (8 + kPrimitiveBytes + 24) + 44;
  }

  // The light and the water's IOR, for the passes that refract at the water.
  void set_light(const gl::Program& p, const Light& light, float ior) const {
    p.set("u_light_type", static_cast<int>(light.type));
    p.set("u_light_direction", v3(light.direction));
    p.set("u_light_position", v3(light.position));
    p.set("u_light_power", light.type == LightType::kDirectional ? light.irradiance : light.intensity);
    p.set("u_ior", ior);
  }

  void ensure_spectral(MapGpu& m) {
    if (m.spectral_size == m.caustics_size && m.color.get()) return;
    const auto size = static_cast<GLsizei>(m.caustics_size);
    GLsizei levels = 1;
    while ((m.caustics_size >> levels) > 0) ++levels;
    m.spectral_sum = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(m.spectral_sum.get(), 1, GL_RGBA32F, size, size);
    m.color = gl::make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(m.color.get(), levels, GL_RGBA32F, size, size);
    glTextureParameteri(m.color.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(m.color.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(m.color.get(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(m.color.get(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    m.spectral_size = m.caustics_size;
  }

  // One traced wavelength's map (level 0, not yet finished) into the sums
  // over wavelengths (caustics_accumulate.comp); the last writes the sum
  // back into the map.
  void accumulate_wavelength(MapGpu& m, const WavelengthSample& w, bool first, bool last) {
    ensure_spectral(m);
    accumulate.use();
    accumulate.set("u_size", static_cast<int>(m.caustics_size));
    accumulate.set("u_rgb", glm::vec3(w.rgb[0], w.rgb[1], w.rgb[2]));
    accumulate.set("u_first", first ? 1 : 0);
    accumulate.set("u_last", last ? 1 : 0);
    glBindImageTexture(0, m.caustics.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(1, m.spectral_sum.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glBindImageTexture(2, m.color.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    const GLuint groups = (m.caustics_size + 7) / 8;
    glDispatchCompute(groups, groups, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT);
    for (GLuint u = 0; u < 3; ++u) glBindImageTexture(u, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    if (last) glGenerateTextureMipmap(m.color.get());
  }

  // Seed 001 ch. 8, GPU variant: render the water along V into the photon
  // texture (splat_photon.frag), copy it into a vertex buffer through the
  // pixel-pack binding (the paper's PBO route), draw it as points with
  // additive blending into the caustics map.
  void draw_splat(MapGpu& m, const CausticsOptions& o, const Light& light, float ior) {
    const BoundingFrame& f = m.lm->frame;
    const std::uint32_t p = o.photons;
    if (photon_size != p) {
      photon_texture = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(photon_texture.get(), 1, GL_RGBA32UI, static_cast<GLsizei>(p), static_cast<GLsizei>(p));
      photon_fbo = gl::make_framebuffer();
      glNamedFramebufferTexture(photon_fbo.get(), GL_COLOR_ATTACHMENT0, photon_texture.get(), 0);
      photon_vbo = gl::make_buffer();
      glNamedBufferStorage(photon_vbo.get(), GLsizeiptr{16} * p * p, nullptr, 0);
      photon_vao = gl::make_vertex_array();
      glVertexArrayVertexBuffer(photon_vao.get(), 0, photon_vbo.get(), 0, 16);
      glEnableVertexArrayAttrib(photon_vao.get(), 0);
      glVertexArrayAttribIFormat(photon_vao.get(), 0, 4, GL_UNSIGNED_INT, 0);
      glVertexArrayAttribBinding(photon_vao.get(), 0, 0);
      photon_size = p;
    }
    // The window: the frame's U-W rectangle grown by a margin, so that
    // photons the waves bend in from beside it are counted.
    constexpr float kMargin = 0.1f;
    const float gx = f.half[0] * (1 + 2 * kMargin), gz = f.half[2] * (1 + 2 * kMargin);
    const glm::vec3 origin(static_cast<float>(f.origin[0]), static_cast<float>(f.origin[1]), static_cast<float>(f.origin[2]));
    glm::mat4 to_clip(0.0f);  // world -> (U / gx, W / gz, 0, 1) about the frame's origin
    for (int k = 0; k < 3; ++k) {
      to_clip[k][0] = f.u[k] / gx;
      to_clip[k][1] = f.w[k] / gz;
    }
    to_clip[3][0] = -glm::dot(v3(f.u), origin) / gx;
    to_clip[3][1] = -glm::dot(v3(f.w), origin) / gz;
    to_clip[3][3] = 1.0f;
    const float zero[4] = {0, 0, 0, 0};
    glBindFramebuffer(GL_FRAMEBUFFER, photon_fbo.get());
    glViewport(0, 0, static_cast<GLsizei>(p), static_cast<GLsizei>(p));
    const GLuint zero_bits[4] = {0, 0, 0, 0};
    glClearNamedFramebufferuiv(photon_fbo.get(), GL_COLOR, 0, zero_bits);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    splat_photon.use();
    splat_photon.set("u_view_proj", to_clip);
    set_frame(splat_photon, f);
    set_light(splat_photon, light, ior);
    splat_photon.set("u_pixel_area", (2 * gx / static_cast<float>(p)) * (2 * gz / static_cast<float>(p)));
    const float texel_u = 2 * f.half[0] / static_cast<float>(m.caustics_size), texel_w = 2 * f.half[2] / static_cast<float>(m.caustics_size);
    splat_photon.set("u_texel_area", texel_u * texel_w);
    splat_photon.set("u_tolerance", m.self_tolerance + 4.0f * 2.0f * std::max(f.half[0], f.half[2]) / static_cast<float>(m.lm->map_size));
    glBindTextureUnit(0, m.position_map.get());
    water->bind_buffers();
    water->draw();

    glBindBuffer(GL_PIXEL_PACK_BUFFER, photon_vbo.get());
    glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT);
    glGetTextureImage(photon_texture.get(), 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, static_cast<GLsizei>(GLsizeiptr{16} * p * p), nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT);

    glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
    glViewport(0, 0, static_cast<GLsizei>(m.caustics_size), static_cast<GLsizei>(m.caustics_size));
    glClearNamedFramebufferfv(m.fbo.get(), GL_COLOR, 0, zero);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    splat_points.use();
    splat_points.set("u_size", static_cast<float>(m.caustics_size));
    glBindVertexArray(photon_vao.get());
    glEnable(GL_PROGRAM_POINT_SIZE);
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(p * p));
    glDisable(GL_PROGRAM_POINT_SIZE);
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    stats.volumes_total += std::uint64_t{p} * p;
  }

  // Alpha = the receiver's presence (caustics_presence.frag), then the mip
  // chain; m.fbo draws into the map's level 0.
  void finish_map(MapGpu& m) {
    glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
    glViewport(0, 0, static_cast<GLsizei>(m.caustics_size), static_cast<GLsizei>(m.caustics_size));
    glColorMaski(0, GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
    presence.use();
    glBindTextureUnit(0, m.position_map.get());
    glBindVertexArray(empty_vao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glGenerateTextureMipmap(m.caustics.get());
  }

  // One wavelength's caustics map into level 0 (finish_map makes its
  // presence and mips).
  void draw_map(MapGpu& m, const CausticsOptions& o, const Light& light, float ior) {
    const BoundingFrame& f = m.lm->frame;
    ensure_planes(m, o);
    ensure_caustics_target(m, o.map_size);
    if (o.method == CausticsMethod::kSplat) {
      draw_splat(m, o, light, ior);
      return;
    }
    const auto nplanes = static_cast<std::uint32_t>(m.planes.size());
    if (nplanes == 0) {  // a map whose sampled surface is empty (e.g. a tiny position map): no caustics
      const float none[4] = {0, 0, 0, 0};
      glClearTexImage(m.caustics.get(), 0, GL_RGBA, GL_FLOAT, none);
      return;
    }

    // 1. Cull: volumes that miss the frame, and (level map) planes the
    // surface under a volume does not need.
    const bool pairs = o.method != CausticsMethod::kVolumetric;
    float lo = 1e30f, hi = -1e30f;
    for (const auto& p : m.planes) {
      lo = std::min(lo, p.offset - p.epsilon);
      hi = std::max(hi, p.offset + p.epsilon);
    }
    // The list is sized by what it last needed, not by the worst case
    // (every volume through every plane): the count is read back after the
    // cull, and the cull re-run with a larger list if it overflowed. Exact
    // for a single frame, at the cost of one small read-back per map.
    if (m.capacity == 0) m.capacity = std::min<std::uint64_t>(kMaxPrimitives, 2ull * water->triangle_count());
    for (int attempt = 0; attempt < 2; ++attempt) {
      if (m.allocated < m.capacity) {
        m.list = gl::make_buffer();
        glNamedBufferStorage(m.list.get(), static_cast<GLsizeiptr>(m.capacity * 8), nullptr, 0);
        m.primitives = gl::make_buffer();
        glNamedBufferStorage(m.primitives.get(), static_cast<GLsizeiptr>(m.capacity) * kPrimitiveBytes, nullptr, 0);
        std::vector<std::uint32_t> idx(m.capacity * 6);
        for (std::uint64_t p = 0; p < m.capacity; ++p) {
          const auto b = static_cast<std::uint32_t>(4 * p);
          const std::uint32_t q[6] = {b, b + 1, b + 3, b, b + 3, b + 2};
          std::copy(q, q + 6, idx.begin() + static_cast<std::ptrdiff_t>(6 * p));
        }
        m.rect_indices = gl::make_buffer();
        glNamedBufferStorage(m.rect_indices.get(), static_cast<GLsizeiptr>(idx.size() * 4), idx.data(), 0);
        m.allocated = m.capacity;
      }
      const std::uint32_t zeros[11] = {};
      glNamedBufferSubData(m.command.get(), 0, sizeof zeros, zeros);
      cull.use();
      set_frame(cull, f);
      cull.set("u_triangles", water->triangle_count());
      cull.set("u_depth_range", glm::vec2(lo, hi));
      cull.set("u_frame_cull", o.cull ? 1 : 0);
      cull.set("u_plane_cull", o.cull ? 1 : 0);
      cull.set("u_pairs", pairs ? 1 : 0);
      cull.set("u_plane_count", static_cast<int>(nplanes));
      // Widen footprints by a caustics texel where the acceptance test
      // samples surface across it (texels coarser than the position map's);
      // at finer texels the depth tiles (8 position texels) already cover it.
      const bool coarse = m.caustics_size < m.lm->map_size;
      cull.set("u_texel", coarse ? glm::vec2(2.0f * f.half[0], 2.0f * f.half[2]) / static_cast<float>(m.caustics_size)
                                 : glm::vec2(0.0f));
      cull.set("u_capacity", static_cast<unsigned>(m.capacity));
      glBindTextureUnit(0, m.depth_tiles.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, flux.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, m.list.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, m.command.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, m.planes_buffer.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, m.primitives.get());
      glDispatchCompute((water->triangle_count() + 63) / 64, 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
      std::uint32_t listed = 0;
      glGetNamedBufferSubData(m.command.get(), 32, 4, &listed);
      if (listed <= m.capacity || m.capacity >= kMaxPrimitives) break;
      m.capacity = std::min<std::uint64_t>(kMaxPrimitives, listed + listed / 4);
    }
    // 2. The list's length becomes the geometry dispatch and the draw count.
    fixup.use();
    fixup.set("u_capacity", static_cast<unsigned>(m.capacity));
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, m.command.get());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, m.command.get());
    geometry.use();
    set_frame(geometry, f);
    geometry.set("u_pairs", pairs ? 1 : 0);
    geometry.set("u_max_magnification", o.max_magnification);
    geometry.set("u_smooth", o.water_smooth ? 1 : 0);
    glProgramUniform2ui(geometry.id(), geometry.loc("u_grid"), water->water().cells[0] + 1, water->water().cells[1] + 1);
    geometry.set("u_map_size", static_cast<float>(m.caustics_size));

    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    const auto size = static_cast<GLsizei>(m.caustics_size);
    const float zero[4] = {0, 0, 0, 0};
    // 3. Geometry of every listed primitive, then 4. one rectangle each.
    auto geometry_then_draw = [&](const gl::Program& draw_program, int plane) {
      geometry.use();
      geometry.set("u_plane", plane);
      glDispatchComputeIndirect(20);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      draw_program.use();
      draw_program.set("u_map_size", static_cast<float>(m.caustics_size));
      glBindVertexArray(empty_vao.get());
      glVertexArrayElementBuffer(empty_vao.get(), m.rect_indices.get());
      glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, nullptr);
    };

    if (pairs) {
      glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
      glViewport(0, 0, size, size);
      glClearNamedFramebufferfv(m.fbo.get(), GL_COLOR, 0, zero);
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
      const float scale = static_cast<float>(m.lm->map_size) / static_cast<float>(m.caustics_size);
      levelmap.set("u_map_scale", glm::vec2(scale));
      levelmap.set("u_samples", static_cast<int>(std::clamp(std::ceil(scale), 1.0f, 4.0f)));
      levelmap.set("u_texels_per_metre", glm::vec2(static_cast<float>(m.caustics_size) / (2 * f.half[0]),
                                                   static_cast<float>(m.caustics_size) / (2 * f.half[2])));
      glBindTextureUnit(0, m.position_map.get());
      geometry_then_draw(levelmap, 0);
    } else {
      // §5.2.1: per sample plane, the receiver's slice image, then the
      // plane's intersection triangles times that slice, then combine.
      ensure_slices(m, nplanes, m.caustics_size);
      glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.get());
      glViewport(0, 0, size, size);
      for (std::uint32_t i = 0; i < nplanes; ++i) {
        glNamedFramebufferTextureLayer(m.fbo.get(), GL_COLOR_ATTACHMENT0, m.slices.get(), 0, static_cast<GLint>(i));
        glClearNamedFramebufferfv(m.fbo.get(), GL_COLOR, 0, zero);
        glDisable(GL_BLEND);
        slab.use();
        set_frame(slab, f);
        slab.set("u_write_depth", 0);
        slab.set("u_near", m.planes[i].offset + m.planes[i].epsilon);
        slab.set("u_far", m.planes[i].offset - m.planes[i].epsilon);
        slab.set("u_model", model_of(m.lm->object));
        draw_object(m.lm->object);

        glNamedFramebufferTextureLayer(m.fbo.get(), GL_COLOR_ATTACHMENT0, m.illumination.get(), 0, static_cast<GLint>(i));
        glClearNamedFramebufferfv(m.fbo.get(), GL_COLOR, 0, zero);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        volumetric.set("u_slice", static_cast<int>(i));
        glBindTextureUnit(0, m.slices.get());
        geometry_then_draw(volumetric, static_cast<int>(i));
      }
      glNamedFramebufferTexture(m.fbo.get(), GL_COLOR_ATTACHMENT0, m.caustics.get(), 0);
      glDisable(GL_BLEND);
      combine.use();
      combine.set("u_count", static_cast<int>(nplanes));
      glBindTextureUnit(0, m.slices.get());
      glBindTextureUnit(1, m.illumination.get());
      glBindVertexArray(empty_vao.get());
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glDisable(GL_BLEND);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindVertexArray(0);
    stats.volumes_total += water->triangle_count();
    stats.planes_drawn += nplanes;
  }
};

CausticsEngine::~CausticsEngine() = default;

Result<std::unique_ptr<CausticsEngine>> CausticsEngine::create(std::vector<LevelMap>& maps, const WaterSurface& water,
                                                               std::function<void(std::uint32_t)> draw_object,
                                                               std::function<glm::mat4(std::uint32_t)> model_of) {
  std::unique_ptr<CausticsEngine> e(new CausticsEngine());
  e->impl_ = std::make_unique<Impl>();
  Impl& s = *e->impl_;
  s.water = &water;
  s.draw_object = std::move(draw_object);
  s.model_of = std::move(model_of);
  const std::string coverage = std::string("#version 450 core\n") + shaders::k_caustics_coverage_glsl;
  const std::string splat_fs = with_optics(shaders::k_splat_photon_frag_glsl);
  const std::string levelmap_vs = insert_after_version(shaders::k_caustics_intersect_vert_glsl, "#define DEPTH_SHIFT\n");
  const std::string levelmap_fs = coverage + shaders::k_caustics_levelmap_frag_glsl;
  const std::string volumetric_fs = coverage + shaders::k_caustics_volumetric_frag_glsl;
  const std::string prepare_src = with_optics(shaders::k_caustics_prepare_comp_glsl);
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs(
      {{&s.levelmap, "caustics_levelmap", levelmap_vs.c_str(), levelmap_fs.c_str()},
       {&s.volumetric, "caustics_volumetric", shaders::k_caustics_intersect_vert_glsl, volumetric_fs.c_str()},
       {&s.slab, "slab", shaders::k_slab_vert_glsl, shaders::k_slab_frag_glsl},
       {&s.splat_photon, "splat_photon", shaders::k_water_vert_glsl, splat_fs.c_str()},
       {&s.splat_points, "splat_points", shaders::k_splat_points_vert_glsl, shaders::k_splat_points_frag_glsl},
       {&s.combine, "volumetric_combine", shaders::k_fullscreen_vert_glsl, shaders::k_volumetric_combine_frag_glsl},
       {&s.presence, "caustics_presence", shaders::k_fullscreen_vert_glsl, shaders::k_caustics_presence_frag_glsl},
       {&s.prepare, "caustics_prepare", prepare_src.c_str()},
       {&s.cull, "caustics_cull", shaders::k_caustics_cull_comp_glsl},
       {&s.fixup, "caustics_fixup", shaders::k_caustics_fixup_comp_glsl},
       {&s.geometry, "caustics_geometry", shaders::k_caustics_geometry_comp_glsl},
       {&s.profile, "profile", shaders::k_profile_comp_glsl},
       {&s.accumulate, "caustics_accumulate", shaders::k_caustics_accumulate_comp_glsl}}));
  s.empty_vao = gl::make_vertex_array();

  s.refracted = gl::make_buffer();
  glNamedBufferStorage(s.refracted.get(), GLsizeiptr{16} * water.vertex_count(), nullptr, 0);
  s.flux = gl::make_buffer();
  glNamedBufferStorage(s.flux.get(), GLsizeiptr{8} * water.triangle_count(), nullptr, 0);

  s.maps.resize(maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i) {
    MapGpu& m = s.maps[i];
    LevelMap& lm = maps[i];
    m.lm = &lm;
    // Position map as frame V per texel (the baked 16-bit depth decoded).
    std::vector<float> v(lm.depth.size());
    for (std::size_t k = 0; k < v.size(); ++k) {
      const std::uint16_t q = lm.depth[k];
      v[k] = q == kEmptyDepth ? kEmptyV
                              : static_cast<float>(lm.frame.half[1] - static_cast<double>(q) / kDepthQuantum * 2.0 * lm.frame.half[1]);
    }
    m.position_map = gl::make_texture(GL_TEXTURE_2D);
    const auto ps = static_cast<GLsizei>(lm.map_size);
    glTextureStorage2D(m.position_map.get(), 1, GL_R32F, ps, ps);
    glTextureSubImage2D(m.position_map.get(), 0, 0, 0, ps, ps, GL_RED, GL_FLOAT, v.data());
    gl::set_sampling(m.position_map.get(), GL_NEAREST);
    s.build_depth_tiles(m);
    m.command = gl::make_buffer();
    glNamedBufferStorage(m.command.get(), 44, nullptr, GL_DYNAMIC_STORAGE_BIT);
  }
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("caustics set-up"));
  return e;
}

Status CausticsEngine::rederive(std::optional<std::uint32_t> light, std::optional<std::uint32_t> object,
                                const std::vector<Light>& lights, const std::optional<Water>& water,
                                const std::vector<std::vector<std::array<double, 3>>>& world) {
  Impl& s = *impl_;
  for (MapGpu& m : s.maps) {
    if ((light && m.lm->light != *light) || (object && m.lm->object != *object)) continue;
    LevelMap& lm = *m.lm;
    const Light& desc = lights[lm.light];
    const auto& pts = world[lm.object];
    double min_y = pts[0][1], max_y = min_y;
    for (const auto& p : pts) {
      min_y = std::min(min_y, p[1]);
      max_y = std::max(max_y, p[1]);
    }
    const glm::mat4 model = s.model_of(lm.object);
    const Vec3d origin{model[3][0], model[3][1], model[3][2]};
    std::string why;
    const auto dir = light_direction(desc, water, origin, min_y, max_y, &why);
    if (!dir) {
      // The light no longer reaches it through the water: an empty map.
      glClearTexImage(m.position_map.get(), 0, GL_RED, GL_FLOAT, &kEmptyV);
      const float empty[2] = {1e30f, -1e30f};
      glClearTexImage(m.depth_tiles.get(), 0, GL_RG, GL_FLOAT, empty);
      continue;
    }
    const double h_old = 2.0 * lm.frame.half[1];
    const bool default_eps = std::fabs(lm.epsilon - h_old / (2.0 * lm.planes_requested)) < 1e-6 * h_old;
    lm.frame = make_frame(dir->travel, pts, origin);
    const BoundingFrame& f = lm.frame;

    // Position map: the receiver seen along -V, nearest surface to the light wins.
    const auto size = static_cast<GLsizei>(lm.map_size);
    if (!m.position_fbo.get()) {
      m.position_fbo = gl::make_framebuffer();
      m.position_depth = gl::make_texture(GL_TEXTURE_2D);
      glTextureStorage2D(m.position_depth.get(), 1, GL_DEPTH_COMPONENT32F, size, size);
      glNamedFramebufferTexture(m.position_fbo.get(), GL_COLOR_ATTACHMENT0, m.position_map.get(), 0);
      glNamedFramebufferTexture(m.position_fbo.get(), GL_DEPTH_ATTACHMENT, m.position_depth.get(), 0);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, m.position_fbo.get());
    glViewport(0, 0, size, size);
    const float empty[4] = {kEmptyV, 0, 0, 0};
    glClearNamedFramebufferfv(m.position_fbo.get(), GL_COLOR, 0, empty);
    const float far_depth = 1.0f;
    glClearNamedFramebufferfv(m.position_fbo.get(), GL_DEPTH, 0, &far_depth);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    s.slab.use();
    set_frame(s.slab, f);
    s.slab.set("u_write_depth", 1);
    s.slab.set("u_near", f.half[1] * 1.0001f);
    s.slab.set("u_far", -f.half[1] * 1.0001f);
    s.slab.set("u_model", model);
    s.draw_object(lm.object);

    // Histogram over the depth levels, then the planes (eq. 4-21, 4-22, 4-6..4-9).
    const auto levels = static_cast<std::uint32_t>(lm.histogram.size());
    if (s.histogram_levels != levels) {
      s.histogram = gl::make_buffer();
      glNamedBufferStorage(s.histogram.get(), GLsizeiptr{4} * levels, nullptr, GL_DYNAMIC_STORAGE_BIT);
      s.histogram_levels = levels;
    }
    const std::uint32_t zero = 0;
    glClearNamedBufferData(s.histogram.get(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    s.profile.use();
    s.profile.set("u_mode", 0);
    s.profile.set("u_levels", levels);
    s.profile.set("u_half_v", f.half[1]);
    glBindTextureUnit(0, m.position_map.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, s.histogram.get());
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    glDispatchCompute((lm.map_size + 7) / 8, (lm.map_size + 7) / 8, 1);
    s.build_depth_tiles(m);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(s.histogram.get(), 0, GLsizeiptr{4} * levels, lm.histogram.data());
    lm.sub_boxes = find_sub_boxes(lm.histogram);
    const double h = 2.0 * f.half[1];
    lm.uniform_planes = uniform_planes(h, lm.planes_requested);
    double used = 0;
    lm.smart_planes = smart_planes(h, levels, lm.sub_boxes, default_eps ? h / (2.0 * lm.planes_requested) : lm.epsilon, &used);
    lm.epsilon = static_cast<float>(used);
    m.planes_valid = false;  // rebuilt from the new profile on the next update
  }
  glDepthMask(GL_TRUE);
  return gl::check_gl("level-map re-derivation");
}

Status CausticsEngine::update_light(std::uint32_t light, const Light& desc, const CausticsOptions& o) {
  Impl& s = *impl_;
  bool any = false;
  for (const MapGpu& m : s.maps) any = any || m.lm->light == light;
  if (!any || o.method == CausticsMethod::kNone) return Status::success();

  // Per traced wavelength (one, at n_d or wavelength_nm, unless the water
  // disperses; issue 22): refract at every water vertex, then each
  // triangle's flux (eq. 2-8, 4-18), then every map of this light; photon
  // splatting refracts per photon instead. Several wavelengths add up in
  // each map's spectral sums (accumulate_wavelength).
  const Water& water = s.water->water();
  const std::vector<WavelengthSample> samples = water_wavelengths(water, o);
  const bool spectral = samples.size() > 1;
  const bool splat = o.method == CausticsMethod::kSplat;
  CausticsStats counted;  // after the first wavelength: the counters count one pass
  for (std::size_t k = 0; k < samples.size(); ++k) {
    // One wavelength and no wavelength_nm: exactly n_d (KHR's 1.5168 is
    // 523655 / 587.56^2 to 4 places only).
    const float ior = spectral || o.wavelength_nm ? index_at(water.ior, water.dispersion, samples[k].nm) : water.ior;
    s.water->bind_buffers();
    if (!splat) {
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, s.refracted.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, s.flux.get());
      s.prepare.use();
      s.set_light(s.prepare, desc, ior);
      s.prepare.set("u_mode", 0);
      s.prepare.set("u_count", s.water->vertex_count());
      glDispatchCompute((s.water->vertex_count() + 63) / 64, 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      s.prepare.set("u_mode", 1);
      s.prepare.set("u_count", s.water->triangle_count());
      glDispatchCompute((s.water->triangle_count() + 63) / 64, 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      s.stats.water_triangles = s.water->triangle_count();
    }
    for (std::size_t i = 0; i < s.maps.size(); ++i) {
      MapGpu& m = s.maps[i];
      if (m.lm->light != light) continue;
      s.draw_map(m, o, desc, ior);
      if (spectral) s.accumulate_wavelength(m, samples[k], k == 0, k + 1 == samples.size());
      if (!splat && k == 0) s.drawn_maps.push_back(i);  // splatting fills no culling counters
    }
    if (k == 0) counted = s.stats;
  }
  s.stats = counted;
  for (MapGpu& m : s.maps) {
    if (m.lm->light != light) continue;
    m.spectral = spectral;
    s.finish_map(m);
    m.gpu_bytes = s.bytes_of(m) + (splat ? std::uint64_t{32} * o.photons * o.photons : 0);
  }
  s.stats.wavelengths = static_cast<std::uint32_t>(samples.size());
  return gl::check_gl("caustics pass");
}

std::optional<CausticsEngine::Binding> CausticsEngine::binding(std::uint32_t object, std::uint32_t light) const {
  for (const MapGpu& m : impl_->maps) {
    if (m.lm->object == object && m.lm->light == light && m.caustics.get()) {
      return Binding{m.lm, m.caustics.get(), m.spectral ? m.color.get() : 0u, m.position_map.get(), m.self_tolerance};
    }
  }
  return std::nullopt;
}

CausticsStats CausticsEngine::stats(bool read_gpu_counters) {
  Impl& s = *impl_;
  CausticsStats out = s.stats;
  out.gpu_bytes = GLsizeiptr{16} * s.water->vertex_count() + GLsizeiptr{8} * s.water->triangle_count();
  for (const MapGpu& m : s.maps) out.gpu_bytes += m.gpu_bytes;
  if (read_gpu_counters) {
    for (std::size_t i : s.drawn_maps) {
      std::uint32_t cmd[11] = {};
      glGetNamedBufferSubData(s.maps[i].command.get(), 0, sizeof cmd, cmd);
      out.volumes_drawn += cmd[10];
      out.overflowed = out.overflowed || cmd[9] != 0;
    }
  }
  return out;
}

void CausticsEngine::reset_stats() {
  impl_->stats = CausticsStats{};
  impl_->drawn_maps.clear();
}

}  // namespace caustix::runtime
