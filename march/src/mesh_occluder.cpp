#include "marchcheck/march/mesh_occluder.hpp"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace marchcheck::march {

struct MeshOccluder::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<int> materials;  // per geometry id
};

MeshOccluder::MeshOccluder(const std::vector<sdf::SceneMesh>& meshes) : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice("threads=1");
  if (!impl_->device) throw std::runtime_error("cannot start Embree");
  impl_->scene = rtcNewScene(impl_->device);
  for (const auto& mesh : meshes) {
    RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), mesh.vertices.size()));
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), mesh.triangles.size()));
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i][k];
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(impl_->scene, geom);
    rtcReleaseGeometry(geom);
    if (impl_->materials.size() <= id) impl_->materials.resize(id + 1, -1);
    impl_->materials[id] = mesh.material;
  }
  rtcCommitScene(impl_->scene);
}

MeshOccluder::~MeshOccluder() {
  rtcReleaseScene(impl_->scene);
  rtcReleaseDevice(impl_->device);
}

MeshHit MeshOccluder::intersect(glm::dvec3 origin, glm::dvec3 direction, double t_max) const {
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
  rtcIntersect1(impl_->scene, &context, &rh);
  MeshHit out;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  out.hit = true;
  out.t = rh.ray.tfar;
  out.normal = glm::normalize(glm::dvec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
  if (glm::dot(out.normal, direction) > 0) out.normal = -out.normal;
  out.material = impl_->materials[rh.hit.geomID];
  return out;
}

}  // namespace marchcheck::march
