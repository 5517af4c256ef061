// The key functions of the exception classes: their vtables and type information are emitted
// here, in the framework library, and only here (see errors.h).
#include <asf/errors.h>

namespace asf {

Error::~Error() = default;
ConfigError::~ConfigError() = default;
PluginError::~PluginError() = default;
InputError::~InputError() = default;

}  // namespace asf
