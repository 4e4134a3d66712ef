// The one conversion point between Eigen (core data: poses, cameras, projection) and GLM (the
// viewer's navigation and GL-facing math). Every conversion copies elements of the same
// scalar type, so round trips are exact.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/rigid3.h"

namespace hdribr::viewer {

// Eigen::Vector3d -> glm::dvec3.
inline glm::dvec3 ToGlm(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
// glm::dvec3 -> Eigen::Vector3d.
inline Eigen::Vector3d ToEigen(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

// Eigen::Vector3f -> glm::vec3.
inline glm::vec3 ToGlm(const Eigen::Vector3f& v) { return {v.x(), v.y(), v.z()}; }
// glm::vec3 -> Eigen::Vector3f.
inline Eigen::Vector3f ToEigen(const glm::vec3& v) { return {v.x, v.y, v.z}; }

// Eigen::Quaterniond -> glm::dquat. Both constructors take (w, x, y, z).
inline glm::dquat ToGlm(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }
// glm::dquat -> Eigen::Quaterniond.
inline Eigen::Quaterniond ToEigen(const glm::dquat& q) {
  return Eigen::Quaterniond(q.w, q.x, q.y, q.z);
}

// 4x4 matrices, Eigen <-> GLM: both store columns first (Eigen's default), so the elements are
// copied in storage order by GLM's make_mat4 and Eigen's Map.
inline glm::dmat4 ToGlm(const Eigen::Matrix4d& m) { return glm::make_mat4(m.data()); }
inline glm::mat4 ToGlm(const Eigen::Matrix4f& m) { return glm::make_mat4(m.data()); }
inline Eigen::Matrix4d ToEigen(const glm::dmat4& m) {
  return Eigen::Map<const Eigen::Matrix4d>(glm::value_ptr(m));
}
inline Eigen::Matrix4f ToEigen(const glm::mat4& m) {
  return Eigen::Map<const Eigen::Matrix4f>(glm::value_ptr(m));
}

// A rigid pose as GL sees it: the homogeneous 4x4 matrix, equal to Rigid3d::Matrix4().
inline glm::dmat4 ToGlm(const Rigid3d& pose) { return ToGlm(pose.Matrix4()); }

}  // namespace hdribr::viewer
