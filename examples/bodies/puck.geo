// A steel puck (a disc 40 mm across, 10 mm high) as a user's own body, for
// docs/your-own-body.md. vibrofric meshes it with tetrahedra sized by fem.mesh,
// finer toward the "contact" surfaces, and places it with its lowest contact
// point on z = 0.
//
// Lengths in metres, like the scene. X slides, Z points up.

SetFactory("OpenCASCADE");

R = 0.02;    // m, radius
H = 0.01;    // m, height
Cylinder(1) = {0, 0, 0,  0, 0, H,  R};

// Faces picked by where they lie (a box around each), not by their numbers.
eps = 1e-6;
bottom() = Surface In BoundingBox {-R - eps, -R - eps, -eps,  R + eps, R + eps, eps};
top() = Surface In BoundingBox {-R - eps, -R - eps, H - eps,  R + eps, R + eps, H + eps};

Physical Surface("contact") = {bottom()};   // the facets that may touch the base
Physical Surface("load") = {top()};         // where F_N presses, as a uniform traction
Physical Volume("puck") = {1};
