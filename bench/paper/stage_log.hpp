// The run's clock and its Reporter (paper_study.hpp), for the stages: stage lines carry the
// seconds since the run began; a Task brackets one long operation with its progress callback.
#pragma once

#include "paper/paper_study.hpp"

#include <chrono>
#include <string>

namespace shprt::paper {

class StageLog {
public:
    explicit StageLog(const Reporter& reporter) : m_reporter(reporter) {}

    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    }
    void say(const std::string& line) const {
        if (m_reporter.stage) m_reporter.stage(elapsed(), line);
    }
    const Reporter& reporter() const { return m_reporter; }

private:
    const Reporter& m_reporter;
    std::chrono::steady_clock::time_point m_start = std::chrono::steady_clock::now();
};

// One long operation (a bake, a ground-truth pass): progress() is the ProgressFn to pass to it;
// end() (or the destructor) tells the reporter that it is over.
class Task {
public:
    Task(const StageLog& log, const std::string& label) : m_reporter(log.reporter()) {
        if (m_reporter.begin_task) m_progress = m_reporter.begin_task(label);
        m_open = true;
    }
    ~Task() { end(); }
    Task(const Task&) = delete;
    Task& operator=(const Task&) = delete;

    const ProgressFn& progress() const { return m_progress; }
    void end() {
        if (m_open && m_reporter.end_task) m_reporter.end_task();
        m_open = false;
    }

private:
    const Reporter& m_reporter;
    ProgressFn m_progress;
    bool m_open = false;
};

}  // namespace shprt::paper
