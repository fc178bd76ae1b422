// libmarchcheck_embree.so: Embree behind embree_module.hpp's table.
#include "embree_module.hpp"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace marchcheck::march {

namespace {

struct Scene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<int> materials;  // per geometry id
};

void* build(const std::vector<sdf::SceneMesh>& meshes) {
  auto s = std::make_unique<Scene>();
  s->device = rtcNewDevice("threads=1");
  if (!s->device) throw std::runtime_error("cannot start Embree");
  s->scene = rtcNewScene(s->device);
  for (const auto& mesh : meshes) {
    RTCGeometry geom = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh.vertices.size()));
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), mesh.triangles.size()));
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i][k];
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(s->scene, geom);
    rtcReleaseGeometry(geom);
    if (s->materials.size() <= id) s->materials.resize(id + 1, -1);
    s->materials[id] = mesh.material;
  }
  rtcCommitScene(s->scene);
  return s.release();
}

void release(void* scene) {
  const std::unique_ptr<Scene> s(static_cast<Scene*>(scene));
  rtcReleaseScene(s->scene);
  rtcReleaseDevice(s->device);
}

MeshHit intersect(const void* scene, glm::dvec3 origin, glm::dvec3 direction, double t_max) {
  const auto* s = static_cast<const Scene*>(scene);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(origin.x);
  rh.ray.org_y = static_cast<float>(origin.y);
  rh.ray.org_z = static_cast<float>(origin.z);
  rh.ray.dir_x = static_cast<float>(direction.x);
  rh.ray.dir_y = static_cast<float>(direction.y);
  rh.ray.dir_z = static_cast<float>(direction.z);
  rh.ray.tnear = 0;
  rh.ray.tfar = std::isfinite(t_max) ? static_cast<float>(t_max) : std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.flags = 0;
  rh.ray.time = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(s->scene, &context, &rh);
  MeshHit out;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  out.hit = true;
  out.t = rh.ray.tfar;
  out.normal = glm::normalize(glm::dvec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
  if (glm::dot(out.normal, direction) > 0) out.normal = -out.normal;
  out.material = s->materials[rh.hit.geomID];
  return out;
}

constexpr EmbreeModule kModule{build, release, intersect};

}  // namespace
}  // namespace marchcheck::march

extern "C" const marchcheck::march::EmbreeModule* marchcheck_embree_module() { return &marchcheck::march::kModule; }
