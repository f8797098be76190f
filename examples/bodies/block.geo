// The paper's block (30 x 40 x 53 mm) as a user's own body: the same hexahedral
// mesh as vibrofric's built-in block at fem.mesh = "coarse" (4 x 5 x 7 elements).
//
// Lengths in metres, like the scene. X slides, Z points up; vibrofric places the
// body with its lowest contact point on z = 0 (this one is there already).
// Extruding a point into a line, the line into a face and the face into a volume,
// each in equal layers of recombined elements, gives hexahedra.

Lx = 0.03;  Ly = 0.04;  Lz = 0.053;   // m
nx = 4;     ny = 5;     nz = 7;       // elements along each edge

Point(1) = {0, 0, 0};
edge[] = Extrude {Lx, 0, 0} { Point{1}; Layers{nx}; Recombine; };
face[] = Extrude {0, Ly, 0} { Line{edge[1]}; Layers{ny}; Recombine; };
body[] = Extrude {0, 0, Lz} { Surface{face[1]}; Layers{nz}; Recombine; };

// body[0] is the top face, body[1] the volume, body[2..5] the sides.
Physical Surface("contact") = {face[1]};   // the bottom face, on the base
Physical Surface("load") = {body[0]};      // the top face, where F_N presses
Physical Volume("block") = {body[1]};
