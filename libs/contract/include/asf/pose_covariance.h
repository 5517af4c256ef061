#pragma once
/// \file pose_covariance.h
/// First-order covariance of the relative poses an edge or its inverse stands for, with
/// composeWithCov and edgeInformation (pose_graph.h): the conversions a front-end's gates
/// and a back-end's propagated marginals share.
#include <asf/pose_graph.h>

#include <Eigen/Core>

namespace asf {

/// Covariance of an edge's mean as additive (x, y, phi) in the frame of `from`, recovered from
/// its information (edgeInformation inverted, without its floor).
Eigen::Matrix3d edgeCovarianceInFrom(const PoseEdge& e);

/// The inverse of a relative pose with first-order covariance (additive x, y, phi; `C` in
/// the frame the pose is expressed in, the result's in the pose's own frame).
mrpt::poses::CPose2D inverseWithCov(const mrpt::poses::CPose2D& p, const Eigen::Matrix3d& C,
                                    Eigen::Matrix3d& out);

}  // namespace asf
