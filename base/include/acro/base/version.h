#pragma once

// Which Acrolab this is: the project's version (CMakeLists.txt, project(… VERSION …)). Recorded
// with every stored analysis so that a newer Acrolab knows to redo it (docs/library.md).

namespace acro {

/// "0.1.0".
const char* AcrolabVersion();

}  // namespace acro
