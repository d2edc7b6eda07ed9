#pragma once
/// Progress and cancellation: the pipeline reports its stage and a fraction done, and asks
/// regularly whether it should stop (it then throws Cancelled). The server implements this
/// with a job's state; the CLI with a progress bar; tests with a counter.

#include <cstddef>
#include <limits>

namespace meshd::core {

enum class Stage { Boundary, Interior, Triangulation, Smoothing, Quality };
const char* to_string(Stage stage);

class Observer {
public:
    virtual ~Observer() = default;
    /// fraction in [0, 1] of the stage. Called often; keep it cheap. The interior, the
    /// triangulation and the smoothing may be announced again, in order, where the boundary
    /// layers are grown again (MeshStats::layer_rounds), and every stage from the boundary on
    /// where the curves are placed again (MeshStats::closing_rounds).
    virtual void on_progress(Stage stage, double fraction) { (void)stage; (void)fraction; }
    virtual bool should_stop() { return false; }
    /// Seconds left before should_stop() says yes for the run's time limit (infinity: no
    /// limit). The pipeline makes no optional round again (MeshStats::closing_rounds) that
    /// would not fit: the mesh made is kept rather than lost to the limit.
    virtual double seconds_left() { return std::numeric_limits<double>::infinity(); }
    /// Once per mesh, after the admission check and before any stage: the points the mesh is
    /// forecast to have and the memory a run of that size needs at its peak
    /// (peak_bytes_for() of mesher.hpp). An observer may wait here (until memory is free) or
    /// throw to refuse the job; the pipeline lets its exception through.
    /// Called again, with more points, each time the interior stage doubles the count it was
    /// forecast (twice the forecast, four times...): a size field with a fine region narrower
    /// than the forecast's samples can hold many times the points forecast. The run holds its
    /// memory by then, so an observer should not wait here; it may throw to stop the run.
    /// Called again too, with the same points and more memory, as a gradation gathers its
    /// sources (from 2^16 on, at each doubling): they stay with the size field to the end of
    /// the run, and where the boundary's triangulation has slivers they outnumber the points.
    /// The interior stage's reports after them count them too.
    virtual void on_forecast(double points, std::size_t peak_bytes) { (void)points; (void)peak_bytes; }
};

}  // namespace meshd::core
