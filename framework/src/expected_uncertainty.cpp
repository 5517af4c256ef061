#include <asf/expected_uncertainty.h>
