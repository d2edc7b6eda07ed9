// The paper's triangulator (section 5): placeholder until implemented.
#include "meshd/core/errors.hpp"
#include "meshd/core/triangulation.hpp"

namespace meshd::core {

TriangulationResult triangulate_advancing_front(const std::vector<Vec2>&, const std::vector<Constraint>&, Observer*) {
    throw InternalError("the advancing-front triangulator is not built yet", __FILE__, __LINE__);
}

}  // namespace meshd::core
