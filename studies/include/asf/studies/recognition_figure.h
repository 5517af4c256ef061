#pragma once
/// \file recognition_figure.h
/// The picture of thesis Fig. 3.3 (`asf recognition --figure`): one node's place-recognition
/// Monte Carlo (asf/planning/place_recognition.h) drawn as SVG.
#include <asf/planning/place_recognition.h>

#include <string>

namespace asf::studies {

/// Fig. 3.3 as SVG: left, the local map (grey), the node's scan (blue), the node (black)
/// and the window of believed poses; right, the samples' position errors in the node's
/// frame [cm], successes (inside the success box) black, failures red, with p in the title.
std::string recognitionScatterSvg(const planning::RecognitionTrial& t, const PoseNode& node,
                                  const planning::RecognitionMcOptions& o, const std::string& title);

}  // namespace asf::studies
