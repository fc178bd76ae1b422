// Packets of rays marched together through the batched tape (sdf::evaluate_batch): each step gathers the rays
// still marching into batches of sdf::kBatch points, so finished rays drop out of the packet. Every ray takes the
// steps, evaluations and t that march() with the one-point tape gives it: the same SphereTrace runs each ray.
#pragma once

#include "marchcheck/march/marcher.hpp"
#include "marchcheck/march/normals.hpp"
#include "marchcheck/sdf/tape.hpp"

namespace marchcheck::march {

// A plain aggregate (PacketRay<T>{} is all zero): the renderer's per-tile arrays of them are filled, not zeroed.
template <class T>
struct PacketRay {
  glm::vec<3, T> origin, direction;
  double max_dist;  // replaces the settings' max_dist for this ray
};

// records[i] = march(tape, rays[i], s with max_dist = rays[i].max_dist, c) for i < n. No allocation.
// T: float or double.
template <class T>
void march_packet(const sdf::Tape& tape, const PacketRay<T>* rays, RayRecord<T>* records, int n,
                  const MarchSettings& s, const MarchContext& c);

// normals[i] = estimate_normal(tape, points[i], central, eps[i]) for i < n: six evaluations each, batched.
template <class T>
void central_normals_packet(const sdf::Tape& tape, const glm::vec<3, T>* points, const T* eps,
                            NormalResult<T>* normals, int n);

}  // namespace marchcheck::march
