// rocking: the umbrella module. It only re-exports the workspace's modules, so
// that an application can `import rocking;` and see the whole public API.
export module rocking;
export import rocking.errors;
export import rocking.quantities;
export import rocking.geometry;
export import rocking.beam;
export import rocking.hysteresis;
export import rocking.devices;
export import rocking.modal;
export import rocking.dynamics;
export import rocking.scene;
export import rocking.ground_motion;
export import rocking.intensity;
export import rocking.fragility;
export import rocking.fitting;
export import rocking.integrator;
export import rocking.sundials;
export import rocking.contact;
export import rocking.simulation;
export import rocking.plot;
export import rocking.study;
export import rocking.study_files;
export import rocking.study_run;
export import rocking.drawing;
export import rocking.report;
export import rocking.run;
export import rocking.lab;
