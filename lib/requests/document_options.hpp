#pragma once
// The options that make or change a design document, as the programs' flags give them and
// the Python module fills them: the electrode array (a document, a uniform array or a grid
// of pads) and the conductor model.  The values are the flags' texts as given: each is
// parsed here, so that a bad one is named by its flag, in the same words from a program
// and from Python (which passes the shortest text of its float).  The programs declare the
// flags in cli/array_options.hpp.

#include <string>

#include "io/document.hpp"

namespace tp {

// --config FILE (- for stdin), or --electrodes N --pitch MM, or --grid CxR --pitch MM
// [--row-pitch MM] [--pad WxL]; empty: not given.
struct ArrayOptions {
  std::string config, electrodes, pitch, grid, row_pitch, pad;
};

// The document from --config, a uniform array (default 8 electrodes at 1 mm), or a grid
// (the rect3d model).
Document load_document(const ArrayOptions& o, int min_electrodes);

// The conductor model's flags: --model (fiber-threshold: --conductor), --z (the 3-D
// models' fibre plane, mm) and --skin (the layered model's skin: a built-in name or a
// file, - for stdin).  Given, they override the document's; empty: not given.
struct ModelOptions {
  std::string model, plane_z, skin;
  std::string flag = "--model";  // the conductor flag's name (fiber-threshold: --conductor)
};
// Applies the options to doc and checks the model against the receptors (bad input).
void apply_model_options(Document& doc, const ModelOptions& o);
// Refuses (bad input) a fibre plane (--z, or the document's model.plane_z_mm) where it
// would be ignored, saying `why`.
void refuse_plane_z(const Document& doc, const ModelOptions& o, const std::string& why);
// The same where the program's --z was applied already: z_given, whether it was given.
void refuse_plane_z(const Document& doc, bool z_given, const std::string& why);

}  // namespace tp
