#include <asf/expected_uncertainty.h>
#include <gtest/gtest.h>
