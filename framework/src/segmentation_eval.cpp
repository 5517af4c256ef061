#include <asf/segmentation_eval.h>
