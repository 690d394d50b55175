"""The shared machine: virtual time and events, axis motion, the path planner, the servo,
outputs tied to motion and the world around the axes. It knows no controller's language,
status letters or wire format; every controller's personality is built on it."""
