// Names of the pipeline's stages, as progress reports and job states show them.

#include "meshd/core/observer.hpp"

namespace meshd::core {

const char* to_string(Stage stage) {
    switch (stage) {
        case Stage::Boundary: return "boundary";
        case Stage::Interior: return "interior";
        case Stage::Triangulation: return "triangulation";
        case Stage::Smoothing: return "smoothing";
        case Stage::Quality: return "quality";
    }
    return "?";
}

}  // namespace meshd::core
