#include <asf/segmentation_eval.h>
#include <gtest/gtest.h>
