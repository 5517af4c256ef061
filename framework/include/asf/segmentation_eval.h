#pragma once
/// \file segmentation_eval.h
/// Scoring of a room segmentation against ground truth (being written).
