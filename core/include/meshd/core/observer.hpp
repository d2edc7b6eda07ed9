#pragma once
/// Progress and cancellation: the pipeline reports its stage and a fraction done, and asks
/// regularly whether it should stop (it then throws Cancelled). The server implements this
/// with a job's state; the CLI with a progress bar; tests with a counter.

namespace meshd::core {

enum class Stage { Boundary, Interior, Triangulation, Smoothing, Quality };
const char* to_string(Stage stage);

class Observer {
public:
    virtual ~Observer() = default;
    /// fraction in [0, 1] of the stage. Called often; keep it cheap.
    virtual void on_progress(Stage stage, double fraction) { (void)stage; (void)fraction; }
    virtual bool should_stop() { return false; }
};

}  // namespace meshd::core
