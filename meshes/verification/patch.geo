// Patch-test mesh: two flat blocks whose interface meshes do not match.
//   tibia (slave)  [0,L] x [0,L] x [0,H_t],        n_t x n_t x nz_t hexahedra
//   femur (master) [0,L] x [0,L] x [H_t,H_t+H_f],  n_f x n_f x nz_f hexahedra
// The two volumes share no geometric entity, so their nodes on z = H_t are
// distinct and the faces are non-matching whenever n_t != n_f.
// Override with: gmsh -3 -setnumber n_t 8 -setnumber n_f 11 patch.geo
Geometry.AutoCoherence = 0; // keep the two bodies' coincident points apart
DefineConstant[ L = 20, H_t = 10, H_f = 6, n_t = 4, n_f = 5, nz_t = 3, nz_f = 2 ];

Point(1) = {0, 0, 0};
lt[] = Extrude {L, 0, 0} { Point{1}; Layers{n_t}; Recombine; };
st[] = Extrude {0, L, 0} { Line{lt[1]}; Layers{n_t}; Recombine; };
vt[] = Extrude {0, 0, H_t} { Surface{st[1]}; Layers{nz_t}; Recombine; };

Point(100) = {0, 0, H_t};
lf[] = Extrude {L, 0, 0} { Point{100}; Layers{n_f}; Recombine; };
sf[] = Extrude {0, L, 0} { Line{lf[1]}; Layers{n_f}; Recombine; };
vf[] = Extrude {0, 0, H_f} { Surface{sf[1]}; Layers{nz_f}; Recombine; };

Physical Volume("tibia") = {vt[1]};
Physical Volume("femur") = {vf[1]};
Physical Surface("tibia_contact") = {vt[0]};
Physical Surface("tibia_inferior") = {st[1]};
Physical Surface("femur_contact") = {sf[1]};
Physical Surface("femur_fixation") = {vf[0]};

Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;
