#include "glass_impl.h"

namespace caustix::runtime {

auto GlassEngine::Impl::sampled_rays(const SceneDesc& scene, const Light& light) const -> std::vector<SampledRay> {
  std::vector<SampledRay> out;
  for (const Glass& g : glass) {
    glm::mat3 rotation;
    float scale = 1;
    decompose(scene.objects[g.object].transform, rotation, scale);
    const glm::mat4 model = to_glm(scene.objects[g.object].transform);
    const glm::mat3 to_object = glm::transpose(rotation);
    const Tables& t = *g.shared;
    for (std::uint32_t k = 0; k < t.sample.vertex_count; ++k) {
      const glm::vec3 p(t.sample_positions[k][0], t.sample_positions[k][1], t.sample_positions[k][2]);
      const glm::vec3 n = glm::normalize(glm::vec3(t.sample_normals[k][0], t.sample_normals[k][1], t.sample_normals[k][2]));
      const glm::vec3 pw(model * glm::vec4(p, 1.0f));
      const glm::vec3 to_light_w = light.type == LightType::kDirectional
                                       ? -glm::normalize(glm::vec3(light.direction[0], light.direction[1], light.direction[2]))
                                       : glm::normalize(glm::vec3(light.position[0], light.position[1], light.position[2]) - pw);
      const glm::vec3 to_light = to_object * to_light_w;
      const float cos_theta = glm::dot(n, to_light);
      if (cos_theta <= 0.0f) continue;  // light enters only where the surface faces it
      const TransportEntry e = lookup(t.sample, k, {n.x, n.y, n.z}, {to_light.x, to_light.y, to_light.z});
      if (e.status != TransportStatus::kLeaves) continue;
      const glm::vec3 exit(model * glm::vec4(glm::vec3(e.exit[0], e.exit[1], e.exit[2]), 1.0f));
      const glm::vec3 d = rotation * glm::vec3(e.direction[0], e.direction[1], e.direction[2]);
      const float tr = static_cast<float>(e.transmittance);
      out.push_back({exit, d, tr, t.sample_areas[k] * scale * scale * cos_theta * tr, g.object});
    }
  }
  return out;
}

auto GlassEngine::Impl::mean_travel(const std::vector<SampledRay>& rays) -> Vec3d {
  Vec3d sum{0, 0, 0};
  for (const SampledRay& r : rays) {
    for (int c = 0; c < 3; ++c) sum[static_cast<std::size_t>(c)] += static_cast<double>(r.direction[c]) * r.transmittance;
  }
  return sum;
}

void GlassEngine::Impl::set_table(const gl::Program& p, const Table& t) {
  const LightTransportTable& q = t.params;
  p.set("u_ltt_resolution", static_cast<int>(q.resolution));
  p.set("u_ltt_exit_min", glm::vec3(q.exit_min[0], q.exit_min[1], q.exit_min[2]));
  p.set("u_ltt_exit_max", glm::vec3(q.exit_max[0], q.exit_max[1], q.exit_max[2]));
  p.set("u_ltt_max_path", q.max_path);
  p.set("u_glass_absorption", glm::vec3(q.absorption[0], q.absorption[1], q.absorption[2]));
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, t.buffer.get());
}

void GlassEngine::Impl::trace_rays(const SceneDesc& scene, const WavelengthSample& w, bool exact_nd, const std::vector<bool>& skip,
                const std::function<void(const gl::Program&)>& set_light_uniforms) {
  const gl::TimedPass timed("glass: rays", gl::PassKind::kCompute);
  for (Glass& g : glass) {
    const Material& m = scene.objects[g.object].material;
    const float n = exact_nd ? m.ior : index_at(m.ior, m.dispersion, w.nm);
    const std::vector<Table>& tables = g.shared->tables;
    std::size_t a = exact_nd ? g.shared->base : 0;
    while (!exact_nd && a + 1 < tables.size() && tables[a + 1].params.ior <= n) ++a;
    // Beyond the tables' range (another writer's tables) the nearest one.
    const bool blend = n > tables[a].params.ior && a + 1 < tables.size();
    for (int pass = 0; pass < (blend ? 2 : 1); ++pass) {
      rays.use();
      set_light_uniforms(rays);
      // The tint at the two crossings (Material::tint) weighs the light as the wavelength does.
      rays.set("u_weight", skip[g.object] ? glm::vec3(0.0f) : glm::vec3(w.rgb[0], w.rgb[1], w.rgb[2]) * transmit(m));
      set_table(rays, tables[a + static_cast<std::size_t>(pass)]);
      rays.set("u_ltt_switch_base", tables[a + static_cast<std::size_t>(pass)].switch_base);  // the view's look-up needs none
      set_pose(rays, scene, g);
      rays.set("u_vertex_count", g.vertices);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.mesh->vertices.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, pass == 0 ? g.rays.get() : g.rays_b.get());
      glDispatchCompute((g.vertices + 63) / 64, 1, 1);
    }
    if (blend) {
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      rays_blend.use();
      rays_blend.set("u_vertex_count", g.vertices);
      rays_blend.set("u_t", (n - tables[a].params.ior) / (tables[a + 1].params.ior - tables[a].params.ior));
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, g.rays.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, g.rays_b.get());
      glDispatchCompute((g.vertices + 63) / 64, 1, 1);
    }
  }
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void GlassEngine::Impl::set_pose(const gl::Program& p, const SceneDesc& scene, const Glass& g) const {
  glm::mat3 rotation;
  float scale = 1;
  decompose(scene.objects[g.object].transform, rotation, scale);
  p.set("u_model", to_glm(scene.objects[g.object].transform));
  p.set("u_rotation", rotation);
  p.set("u_scale", scale);
}

void GlassEngine::Impl::illuminate(const SceneDesc& scene, Target& t, const CausticsOptions& co,
                const std::function<void(const gl::Program&)>& set_light_uniforms, bool coarse) {
  const int size = t.size;
  const std::uint32_t planes = t.planes;
  glBindFramebuffer(GL_FRAMEBUFFER, t.fbo.get());
  glViewport(0, 0, size, size);
  for (std::size_t gi = 0; gi < glass.size(); ++gi) {
    Glass& g = glass[gi];
    const std::uint64_t per_plane = std::uint64_t{g.triangles} * 3;  // the triangle or its corner beams
    const std::uint64_t prims = per_plane * planes;
    // One buffer for every target and glass object, one after the
    // other: the barrier keeps the last one's draws from seeing this
    // one's geometry (llvmpipe bins draws until it flushes).
    if (prims > primitive_capacity) {
      primitives = gl::make_buffer();
      glNamedBufferStorage(primitives.get(), static_cast<GLsizeiptr>(prims * kPrimitiveBytes), nullptr, 0);
      primitive_capacity = prims;
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    std::optional<gl::TimedPass> timed;
    timed.emplace("glass: geometry", gl::PassKind::kCompute);
    geometry.use();
    geometry.set("u_origin", glm::vec3(static_cast<float>(t.frame.origin[0]), static_cast<float>(t.frame.origin[1]),
                                       static_cast<float>(t.frame.origin[2])));
    geometry.set("u_U", glm::vec3(t.frame.u[0], t.frame.u[1], t.frame.u[2]));
    geometry.set("u_V", glm::vec3(t.frame.v[0], t.frame.v[1], t.frame.v[2]));
    geometry.set("u_W", glm::vec3(t.frame.w[0], t.frame.w[1], t.frame.w[2]));
    geometry.set("u_half", glm::vec3(t.frame.half[0], t.frame.half[1], t.frame.half[2]));
    set_light_uniforms(geometry);
    geometry.set("u_model", to_glm(scene.objects[g.object].transform));
    geometry.set("u_triangle_count", g.triangles);
    geometry.set("u_plane_count", planes);
    glProgramUniform1fv(geometry.id(), geometry.loc("u_plane_v"), static_cast<GLsizei>(planes), t.plane_v.data());
    geometry.set("u_map_size", static_cast<float>(size));
    geometry.set("u_max_magnification", co.max_magnification);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.mesh->vertices.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, g.rays.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, g.mesh->indices.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, primitives.get());
    glDispatchCompute(static_cast<GLuint>((prims + 63) / 64), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    // Smooth caustics: each whole triangle's corner intensities.
    if (co.glass_smooth) {
      corner_intensity.use();
      corner_intensity.set("u_triangle_count", g.triangles);
      corner_intensity.set("u_plane_count", planes);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, g.shared->ring_offsets.get());
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, g.shared->ring_triangles.get());
      glDispatchCompute(static_cast<GLuint>((std::uint64_t{g.triangles} * planes + 63) / 64), 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    timed.emplace("glass: illumination", gl::PassKind::kRaster);
    illumination.set("u_smooth", co.glass_smooth ? 1 : 0);
    illumination_wide.set("u_smooth", co.glass_smooth ? 1 : 0);
    glBindTextureUnit(0, t.target.get());
    glBindVertexArray(empty_vao.get());
    // The main layers, then the focus window's: the same
    // primitives, their texel coordinates q taken to the window's
    // (q - offset) * scale, over the layer's lower corner
    // (kFocusTexels: 0.42 of the fragments of a full layer); a
    // coarse window (update_light) at half that scale into the square
    // beside it (window_squares), which resolve_window interpolates.
    const float half = t.focus[2];
    const WindowSquares sq = window_squares(size);
    for (int window = 0; window < (half > 0.0f ? 2 : 1); ++window) {
      const float s = static_cast<float>(size);
      glm::vec3 map = window == 0 ? glm::vec3(0.0f, 0.0f, 1.0f)
                                  : glm::vec3(s * (t.focus[0] - half), s * (t.focus[1] - half), kFocusTexels / (2.0f * half));
      int side = window == 0 ? size : sq.side;
      glViewport(0, 0, side, side);
      if (window == 1 && coarse) {
        // Half the texels a side, into the square at (sq.side, sq.side):
        // (q - xy) * z / 2 + sq.side. The whole layer's viewport keeps
        // gl_FragCoord in that map; the scissor keeps the light in it.
        // (glass_focus_wide then counts the square's texels.)
        const float shift = static_cast<float>(sq.side) / (0.5f * map.z);
        map = glm::vec3(map.x - shift, map.y - shift, 0.5f * map.z);
        side = size;
        glViewport(0, 0, size, size);
        glScissor(sq.side, sq.side, sq.coarse_side, sq.coarse_side);
        glEnable(GL_SCISSOR_TEST);
      }
      // In the window the wide primitives (CausticsOptions::
      // glass_focus_wide window texels high) are the second program's
      // (glass_window_split.glsl): on glass_teapot with the light moving
      // they were most of the window's fragments.
      const float wide = window == 0 || !std::isfinite(co.glass_focus_wide) ? 0.0f : std::max(co.glass_focus_wide, 0.0f);
      for (const gl::Program* p : {&illumination, &illumination_wide}) {
        p->set("u_map_size", static_cast<float>(side));  // texels to clip space over the viewport
        p->set("u_texel_map", map);
        p->set("u_wide_texels", wide);
      }
      illumination.set("u_tent", window == 1 && co.glass_focus_tent ? 1 : 0);
      for (std::uint32_t k = 0; k < planes; ++k) {
        const GLint layer = static_cast<GLint>(k + (window == 0 ? 0 : planes));
        glNamedFramebufferTextureLayer(t.fbo.get(), GL_COLOR_ATTACHMENT0, t.illumination.get(), 0, layer);
        // Six vertices a primitive (caustics_intersect.vert, either
        // program), plane k's from k * per_plane.
        illumination.use();
        glDrawArrays(GL_TRIANGLES, static_cast<GLint>(k * per_plane * 6), static_cast<GLsizei>(per_plane * 6));
        if (window == 0) continue;
        illumination_wide.use();
        glDrawArrays(GL_TRIANGLES, static_cast<GLint>(k * per_plane * 6), static_cast<GLsizei>(per_plane * 6));
      }
      if (window == 1 && coarse) glDisable(GL_SCISSOR_TEST);
    }
  }
}

void GlassEngine::Impl::ensure_target(Target& t, int size, std::uint32_t planes, bool focus) {
  const std::uint32_t layers = focus || (t.layers == 2 * planes && t.size == size) ? 2 * planes : planes;
  if (t.size == size && t.planes == planes && t.layers == layers && t.fbo.get()) return;
  t.size = size;
  t.planes = planes;
  t.layers = layers;
  t.target = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(t.target.get(), 1, GL_RGBA32F, size, size);
  t.depth = gl::make_texture(GL_TEXTURE_2D);
  glTextureStorage2D(t.depth.get(), 1, GL_DEPTH_COMPONENT32F, size, size);
  t.illumination = gl::make_texture(GL_TEXTURE_2D_ARRAY);
  // With a focus window, a mip chain: its texels are finer than the
  // pixels that usually look at them (0.6 mm on glass_ball's floor), and
  // a focus sampled at a pixel's centre alone would flicker as the view
  // moves; the mips average it (and keep the mean irradiance).
  t.levels = 1;
  while (layers > planes && (size >> t.levels) > 0) ++t.levels;
  glTextureStorage3D(t.illumination.get(), t.levels, GL_RGBA32F, size, size, static_cast<GLsizei>(layers));
  for (GLuint tex : {t.target.get(), t.illumination.get()}) {
    gl::set_sampling(tex, GL_LINEAR);
  }
  if (t.levels > 1) glTextureParameteri(t.illumination.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(t.target.get(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.target.get(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  t.fbo = gl::make_framebuffer();
}

GlassEngine::~GlassEngine() = default;

Result<std::unique_ptr<GlassEngine>> GlassEngine::create(const SceneDesc& scene,
                                                         const std::vector<LightTransportTable>& tables,
                                                         const std::vector<LightTransportTable>& spectral,
                                                         const std::vector<GpuMesh>& meshes,
                                                         const std::vector<TriangleMesh>& cpu_meshes,
                                                         std::function<void(std::uint32_t)> draw_object,
                                                         const std::string& lighting_prefix) {
  std::unique_ptr<GlassEngine> e(new GlassEngine());
  e->impl_ = std::make_unique<Impl>();
  Impl& s = *e->impl_;
  s.draw_object = std::move(draw_object);
  const std::string version = "#version 450 core\n";
  const std::string rays_src =
      insert_after_version(lighting_prefix.c_str(), "#define CAUSTIX_NO_DERIVATIVES\n") + shaders::k_transport_glsl + shaders::k_glass_rays_comp_glsl;
  const std::string surface_vs = version + shaders::k_transport_glsl + shaders::k_glass_surface_vert_glsl;
  const std::string environment = shaders::k_glass_environment_glsl;
  const std::string surface_fs = with_optics((environment + shaders::k_glass_surface_frag_glsl).c_str());
  const std::string nearby_fs = with_optics((environment + shaders::k_glass_nearby_frag_glsl).c_str());
  const std::string thin_fs = with_optics((environment + shaders::k_glass_thin_frag_glsl).c_str());
  const std::string stride = "#define PRIM_STRIDE 6\n#define TEXEL_MAP\n";
  const std::string illum_vs =
      insert_after_version(shaders::k_caustics_intersect_vert_glsl, stride + "#define GLASS_TENT\n" + shaders::k_glass_window_split_glsl);
  const std::string wide_fs = version + stride + shaders::k_caustics_coverage_glsl + shaders::k_glass_illumination_wide_frag_glsl;
  const std::string wide_vs =
      insert_after_version(shaders::k_caustics_intersect_vert_glsl, stride + "#define GLASS_WIDE\n" + shaders::k_glass_window_split_glsl);
  const std::string illum_fs = version + stride + shaders::k_caustics_coverage_glsl + shaders::k_glass_illumination_frag_glsl;
  const std::string geometry_src = insert_after_version(shaders::k_glass_geometry_comp_glsl, std::string("#define CAUSTIX_OPTICS_ONLY\n") + shaders::k_caustix_glsl);
  CAUSTIX_RETURN_IF_ERROR(gl::build_programs(
      {{&s.rays, "glass_rays", rays_src.c_str()},
       {&s.rays_blend, "glass_rays_blend", shaders::k_glass_rays_blend_comp_glsl},
       {&s.geometry, "glass_geometry", geometry_src.c_str()},
       {&s.corner_intensity, "glass_corner_intensity", shaders::k_glass_corner_intensity_comp_glsl},
       {&s.target_program, "glass_target", shaders::k_mesh_vert_glsl, shaders::k_glass_target_frag_glsl},
       {&s.illumination, "glass_illumination", illum_vs.c_str(), illum_fs.c_str()},
       {&s.illumination_wide, "glass_illumination_wide", wide_vs.c_str(), wide_fs.c_str()},
       {&s.window_resolve, "glass_window_resolve", shaders::k_glass_window_resolve_comp_glsl},
       {&s.surface, "glass_surface", surface_vs.c_str(), surface_fs.c_str()},
       {&s.back_faces, "glass_back", shaders::k_mesh_vert_glsl, shaders::k_glass_back_frag_glsl},
       {&s.nearby, "glass_nearby", shaders::k_mesh_vert_glsl, nearby_fs.c_str()},
       {&s.thin_view, "glass_thin", shaders::k_mesh_vert_glsl, thin_fs.c_str()},
       {&s.composite, "glass_composite", shaders::k_fullscreen_vert_glsl, shaders::k_glass_composite_frag_glsl}}));
  s.nearest = gl::make_nearest_sampler();

  // One set of tables per object that has its own (LTTB); objects that use
  // another's (Object::tables_from) draw from the same buffers.
  std::vector<const Impl::Tables*> set_of(scene.objects.size(), nullptr);
  for (const LightTransportTable& t : tables) {
    auto set = std::make_unique<Impl::Tables>();
    Impl::Tables& ts = *set;
    ts.tables.push_back(Impl::Table{t, {}});
    for (const LightTransportTable& q : spectral) {
      if (q.object == t.object) ts.tables.push_back(Impl::Table{q, {}});
    }
    // Ascending IOR (the spectral tables descend with wavelength), n_d's among them.
    std::stable_sort(ts.tables.begin(), ts.tables.end(), [](const Impl::Table& a, const Impl::Table& b) { return a.params.ior < b.params.ior; });
    const TriangleMesh& mesh = cpu_meshes[scene.objects[t.object].mesh_index];
    if (mesh.positions.size() != t.vertex_count) return make_error(ErrorCode::kInternal, "glass mesh and its transport table disagree on vertices");
    for (std::size_t k = 0; k < ts.tables.size(); ++k) {
      Impl::Table& table = ts.tables[k];
      if (table.params.wavelength_nm == 0) {
        ts.base = k;
        // Every k-th vertex's rows, at most kSampleBytes of them (and at
        // least kMinSampleVertices vertices).
        const LightTransportTable& full = table.params;
        const std::size_t row = std::size_t{full.resolution} * full.resolution * 4;  // words per vertex
        const std::size_t want = std::max<std::size_t>(kMinSampleVertices, kSampleBytes / (row * 4));
        const std::size_t every = std::max<std::size_t>(1, (full.vertex_count + want - 1) / want);
        ts.sample = full;
        ts.sample.words.clear();
        ts.sample.vertex_count = 0;
        std::vector<double> share(full.vertex_count, 0.0);  // a third of each vertex's one-ring area
        for (const auto& tri : mesh.triangles) {
          const auto& a = mesh.positions[tri[0]];
          const auto& b = mesh.positions[tri[1]];
          const auto& c = mesh.positions[tri[2]];
          const glm::dvec3 e1(b[0] - a[0], b[1] - a[1], b[2] - a[2]), e2(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
          const double third = glm::length(glm::cross(e1, e2)) / 6.0;
          for (const std::uint32_t v : tri) {
            if (v < share.size()) share[v] += third;
          }
        }
        for (std::size_t v = 0; v < full.vertex_count; v += every) {
          ts.sample.words.insert(ts.sample.words.end(), full.words.begin() + static_cast<std::ptrdiff_t>(v * row),
                                 full.words.begin() + static_cast<std::ptrdiff_t>((v + 1) * row));
          ts.sample_positions.push_back(mesh.positions[v]);
          ts.sample_normals.push_back(mesh.normals[v]);
          ts.sample_areas.push_back(static_cast<float>(share[v] * static_cast<double>(std::min(every, full.vertex_count - v))));
          ++ts.sample.vertex_count;
        }
      }
      // The switch bytes (LTTW) after the entries, padded to a word.
      std::vector<std::uint32_t>& words = table.params.words;
      if (!table.params.switches.empty()) {
        table.switch_base = static_cast<std::uint32_t>(words.size());
        words.resize(words.size() + (table.params.switches.size() + 3) / 4, 0);
        std::memcpy(words.data() + table.switch_base, table.params.switches.data(), table.params.switches.size());
      }
      table.buffer = gl::make_buffer();
      glNamedBufferStorage(table.buffer.get(), static_cast<GLsizeiptr>(words.size() * 4), words.data(), 0);
      ts.gpu_bytes += words.size() * 4;
      words.clear();
      words.shrink_to_fit();
      table.params.switches.clear();
      table.params.switches.shrink_to_fit();
    }
    // One-rings from the mesh's triangles (the order the LTT indexes and the GPU draws).
    std::vector<std::uint32_t> idx;
    idx.reserve(mesh.triangles.size() * 3);
    for (const auto& tri : mesh.triangles) idx.insert(idx.end(), tri.begin(), tri.end());
    std::vector<std::uint32_t> offsets(std::size_t{t.vertex_count} + 1, 0), ring(idx.size());
    for (std::uint32_t v : idx) {
      if (v >= t.vertex_count) return make_error(ErrorCode::kInternal, "glass mesh index beyond its transport table's vertices");
      ++offsets[v + 1];
    }
    for (std::size_t v = 0; v < t.vertex_count; ++v) offsets[v + 1] += offsets[v];
    std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t k = 0; k < idx.size(); ++k) ring[fill[idx[k]]++] = static_cast<std::uint32_t>(k / 3);
    ts.ring_offsets = gl::make_buffer();
    glNamedBufferStorage(ts.ring_offsets.get(), static_cast<GLsizeiptr>(offsets.size() * 4), offsets.data(), 0);
    ts.ring_triangles = gl::make_buffer();
    glNamedBufferStorage(ts.ring_triangles.get(), static_cast<GLsizeiptr>(std::max<std::size_t>(ring.size(), 1) * 4), ring.data(), 0);
    ts.gpu_bytes += offsets.size() * 4 + std::max<std::size_t>(ring.size(), 1) * 4;
    set_of[t.object] = set.get();
    s.table_sets.push_back(std::move(set));
  }
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    if (!is_transparent(o.role)) continue;
    Impl::Glass g;
    g.object = i;
    g.mesh = &meshes[o.mesh_index];
    g.shared = set_of[o.tables_from.value_or(i)];
    if (!g.shared) return make_error(ErrorCode::kInternal, "transparent object '" + o.name + "' has no light-transport table");
    g.vertices = g.shared->tables[g.shared->base].params.vertex_count;
    g.triangles = static_cast<std::uint32_t>(g.mesh->index_count / 3);
    g.rays = gl::make_buffer();
    glNamedBufferStorage(g.rays.get(), static_cast<GLsizeiptr>(std::size_t{g.vertices} * kRayBytes), nullptr, 0);
    if (g.shared->tables.size() > 1) {
      g.rays_b = gl::make_buffer();
      glNamedBufferStorage(g.rays_b.get(), static_cast<GLsizeiptr>(std::size_t{g.vertices} * kRayBytes), nullptr, 0);
      s.spectral = true;
    }
    s.glass.push_back(std::move(g));
  }
  for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
    if (is_thin(scene.objects[i].role)) s.thin.push_back(Impl::Thin{i, &meshes[scene.objects[i].mesh_index]});
  }
  // A target per (opaque object, light): every light's textures stay valid
  // together, for applications that light several views after one update.
  // None without solid glass: thin-walled glass sends no table light.
  for (std::uint32_t li = 0; li < scene.lights.size() && !s.glass.empty(); ++li) {
    for (std::uint32_t i = 0; i < scene.objects.size(); ++i) {
      if (transmits(scene.objects[i].role)) continue;
      Impl::Target t;
      t.object = i;
      t.light = li;
      s.targets.push_back(std::move(t));
    }
  }
  s.empty_vao = gl::make_vertex_array();
  s.made.resize(scene.lights.size());
  CAUSTIX_RETURN_IF_ERROR(gl::check_gl("glass set-up"));
  return e;
}

Status GlassEngine::update_light(const SceneDesc& scene, std::uint32_t li, const CausticsOptions& co,
                                 const std::vector<std::vector<std::array<double, 3>>>& world_vertices,
                                 const std::vector<bool>& by_caustic_maps,
                                 const std::function<void(const gl::Program&)>& set_light_uniforms, const SceneVersions& versions,
                                 bool due, EffectWork& work) {
  Impl& s = *impl_;
  if (s.glass.empty()) return Status::success();  // thin-walled glass only: the caustic maps carry its light
  const LightInputs key{SceneVersions{versions.light, versions.transforms, 0}, co};  // not the water's
  if (s.made.decide(li, key, due, work) != Refresh::kRemake) return Status::success();
  s.made.made(li, key);
  const Light& light = scene.lights[li];
  // The traced wavelengths: a monochromatic image's, the bins of
  // dispersive glass with tables at other wavelengths, else the d line.
  std::vector<WavelengthSample> waves(1);
  if (co.wavelength_nm) {
    waves[0].nm = *co.wavelength_nm;
  } else if (s.spectral) {
    waves = wavelength_samples(co.wavelengths);
  }
  const bool exact_nd = !co.wavelength_nm && waves.size() == 1;
  s.traced = static_cast<std::uint32_t>(waves.size());
  // 1. Outgoing rays of every transparent vertex (§4.1) at the first
  // wavelength, and the mean transmitted direction (at n_d: the frames
  // serve every wavelength).
  s.trace_rays(scene, waves[0], exact_nd, by_caustic_maps, set_light_uniforms);
  const std::vector<Impl::SampledRay> sampled = s.sampled_rays(scene, light);
  Vec3d travel = Impl::mean_travel(sampled);
  double len = std::sqrt(travel[0] * travel[0] + travel[1] * travel[1] + travel[2] * travel[2]);
  if (len < 1e-9) {  // nothing transmitted: any frame will do
    travel = {light.direction[0], light.direction[1], light.direction[2]};
    if (light.type == LightType::kPoint) travel = {0, -1, 0};
    len = std::sqrt(travel[0] * travel[0] + travel[1] * travel[1] + travel[2] * travel[2]);
  }
  for (double& c : travel) c /= len;

  const int size = static_cast<int>(std::clamp<std::uint32_t>(co.glass_map_size, 1, 8192));
  const std::uint32_t wanted = std::clamp<std::uint32_t>(co.glass_planes, 1, kMaxGlassPlanes);
  glDisable(GL_CULL_FACE);
  for (Impl::Target& t : s.targets) {
    if (t.light != li) continue;
    // 2. The virtual camera along the mean transmitted direction, tight
    // around the target, and n planes across its depth (§4.2). A flat
    // target (a floor) is looked at along its normal instead, from its lit
    // side: it then lies in one plane, which the transmitted rays are cut
    // with exactly. Across the mean direction a floor spans the whole depth
    // range, and interpolating between planes that cut the glass object
    // (rays leave below some of them) lost 46 % of glass_teapot's light
    // and placed the rest up to 0.5 m off (docs/glass.md).
    const Object& o = scene.objects[t.object];
    if (t.flat_checked_at != o.transform) {
      t.flat_normal = plane_normal(world_vertices[t.object]);
      t.flat_checked_at = o.transform;
    }
    Vec3d view = travel;
    if (const auto& n = t.flat_normal) {
      const double side = n->at(0) * travel[0] + n->at(1) * travel[1] + n->at(2) * travel[2] < 0 ? -1.0 : 1.0;
      view = {side * n->at(0), side * n->at(1), side * n->at(2)};
    }
    t.frame = make_frame(view, world_vertices[t.object], {o.transform[12], o.transform[13], o.transform[14]});
    const float hv = t.frame.half[1];
    const std::uint32_t planes = hv > 1e-5f * std::max(t.frame.half[0], t.frame.half[2]) ? wanted : 1;
    t.plane_v.resize(planes);
    for (std::uint32_t k = 0; k < planes; ++k) t.plane_v[k] = planes == 1 ? 0.0f : hv - 2.0f * hv * static_cast<float>(k) / static_cast<float>(planes - 1);
    // The last window is kept while it serves (at the same texture size).
    const std::array<float, 3> last = t.size == size ? t.focus : std::array<float, 3>{0, 0, 0};
    t.focus = co.glass_focus ? Impl::focus_window(t, sampled, by_caustic_maps, last, size) : std::array<float, 3>{0, 0, 0};
    s.ensure_target(t, size, planes, t.focus[2] > 0);
    const glm::vec3 origin(static_cast<float>(t.frame.origin[0]), static_cast<float>(t.frame.origin[1]), static_cast<float>(t.frame.origin[2]));
    const glm::vec3 U(t.frame.u[0], t.frame.u[1], t.frame.u[2]), V(t.frame.v[0], t.frame.v[1], t.frame.v[2]),
        W(t.frame.w[0], t.frame.w[1], t.frame.w[2]), half(t.frame.half[0], t.frame.half[1], t.frame.half[2]);

    // 3. The target's normals and depth from the virtual camera.
    const gl::TimedPass timed("glass: targets", gl::PassKind::kRaster);
    glNamedFramebufferTexture(t.fbo.get(), GL_COLOR_ATTACHMENT0, t.target.get(), 0);
    glNamedFramebufferTexture(t.fbo.get(), GL_DEPTH_ATTACHMENT, t.depth.get(), 0);
    glBindFramebuffer(GL_FRAMEBUFFER, t.fbo.get());
    glViewport(0, 0, size, size);
    const float none[4] = {0, 0, 0, -1e30f};
    glClearNamedFramebufferfv(t.fbo.get(), GL_COLOR, 0, none);
    glDepthMask(GL_TRUE);  // before the clear, which obeys it
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);
    s.target_program.use();
    s.target_program.set("u_origin", origin);
    s.target_program.set("u_V", V);
    // Orthographic along -V over the frame's U, W extents; nearer the light
    // is smaller depth: clip = ((r.U) / hu, (r.W) / hw, -(r.V) / (1.01 hv)), r = p - origin.
    glm::mat4 camera(0.0f);
    const glm::vec3 rows[3] = {U / half.x, W / half.z, -V / (1.01f * half.y)};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) camera[c][r] = rows[r][c];
      camera[3][r] = -glm::dot(rows[r], origin);
    }
    camera[3][3] = 1.0f;
    s.target_program.set("u_view_proj", camera);
    Impl::set_mesh_pose(s.target_program, o);
    s.draw_object(t.object);
    glClearTexImage(t.illumination.get(), 0, GL_RGBA, GL_FLOAT, nullptr);
    glNamedFramebufferTexture(t.fbo.get(), GL_DEPTH_ATTACHMENT, 0, 0);
    t.valid = true;
  }

  // 4. Illumination textures: every glass triangle's volume cut by every
  // plane, splatted with exact coverage and eq. 3; each traced wavelength
  // adds its rays' light (weighted by its bin) into the same textures.
  glDisable(GL_DEPTH_TEST);
  // Where glass disperses a focus window is drawn once per traced
  // wavelength (the dispersive ball: 8 times), and at its own texels it
  // cost that ball's frame +26-31 % with the light turning (llvmpipe).
  // With CausticsOptions::glass_focus_spectral_coarse such a window is
  // drawn at half its texels a side and interpolated into its own
  // (resolve_window): docs/glass-focus.md, "A window per wavelength". A
  // monochromatic image (CausticsOptions::wavelength_nm) is drawn the same
  // way, so that it is what the RGB image sums; one wavelength (the d line
  // alone) is the glass without dispersion, as drawn without it.
  const bool spectral_window = co.glass_focus_spectral_coarse && s.spectral && (waves.size() > 1 || co.wavelength_nm.has_value());
  const auto coarse_window = [&](const Impl::Target& t) {
    return spectral_window && t.focus[2] > 0.0f && Impl::window_squares(t.size).coarse;
  };
  for (std::size_t k = 0; k < waves.size(); ++k) {
    if (k > 0) {
      // The primitives the last wavelength's draws read are rewritten below.
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      s.trace_rays(scene, waves[k], exact_nd, by_caustic_maps, set_light_uniforms);
    }
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    for (Impl::Target& t : s.targets) {
      if (t.light != li) continue;
      s.illuminate(scene, t, co, set_light_uniforms, coarse_window(t));
    }
    glDisable(GL_BLEND);
  }
  for (Impl::Target& t : s.targets) {
    if (t.light == li && coarse_window(t)) s.resolve_window(t);
  }
  for (Impl::Target& t : s.targets) {
    if (t.light != li || t.levels == 1) continue;
    const gl::TimedPass timed("glass: mips", gl::PassKind::kRaster);
    glGenerateTextureMipmap(t.illumination.get());
  }
  glBindVertexArray(0);
  return gl::check_gl("glass caustics");
}

std::vector<ExitRay> GlassEngine::exit_sample(const SceneDesc& scene, std::uint32_t light) const {
  std::vector<ExitRay> out;
  for (const Impl::SampledRay& r : impl_->sampled_rays(scene, scene.lights[light])) out.push_back({r.exit, r.direction, r.flux});
  return out;
}

std::optional<GlassEngine::Binding> GlassEngine::binding(std::uint32_t object, std::uint32_t light) const {
  for (const Impl::Target& t : impl_->targets) {
    if (t.object != object || t.light != light || !t.valid) continue;
    const float texel = 2.0f * std::max(t.frame.half[0], t.frame.half[2]) / static_cast<float>(t.size);
    return Binding{t.frame, t.plane_v, t.illumination.get(), t.target.get(), 2.0f * texel + 1e-4f * t.frame.half[1], t.focus};
  }
  return std::nullopt;
}


std::uint64_t GlassEngine::times_made(std::uint32_t li) const { return impl_->made.times_made(li); }

std::uint64_t GlassEngine::gpu_bytes() const {
  std::uint64_t b = 0;
  for (const auto& set : impl_->table_sets) b += set->gpu_bytes;  // once however many objects share them
  for (const Impl::Glass& g : impl_->glass) b += std::uint64_t{g.vertices} * kRayBytes * (g.rays_b.get() ? 2 : 1);  // rays
  for (const Impl::Target& t : impl_->targets) {
    const std::uint64_t texels = std::uint64_t(t.size) * static_cast<std::uint64_t>(t.size);
    b += texels * (16 + 4) + texels * 16 * t.layers * (t.levels > 1 ? 4 : 3) / 3;  // mips: a third more
  }
  return b + impl_->primitive_capacity * kPrimitiveBytes;
}


std::uint32_t GlassEngine::wavelengths() const { return impl_->traced; }

}  // namespace caustix::runtime
