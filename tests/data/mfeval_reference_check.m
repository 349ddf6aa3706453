% Recompute tyrefit's MFeval reference values with MFeval itself (MATLAB, or GNU Octave >= 7).
%
% Needs MFeval 4.x's +mfeval package folder on the path (readTIR and Solver are called directly,
% as mfeval.m does; in Octave, put only the folder holding +mfeval/ on the path, not mfeval.m,
% whose name would hide the package), for example
% mathworks/Simscape-Vehicle-Templates @ 0a17f155c510f1143b9296e03068e82470c251b2,
% Libraries/Vehicle/Tire/MFEval/MFeval_4p0/MFeval.  Run from tests/data:
%
%     octave --no-gui mfeval_reference_check.m
%
% For every row of mfeval_mf61_reference.csv ('file' rows; the 'scaled' rows need the scaling
% factors of mfeval_REFERENCE.md set in the parameter structure) it calls
% MFeval's solver with useMode 111 on [Fz kappa alpha gamma phit Vx P] and prints the largest difference to the
% stored Fx, Fy, Mx, My, Mz as a percentage of each channel's peak.
fid = fopen('mfeval_mf61_reference.csv');
fgetl(fid);
C = textscan(fid, '%s %s %f %f %f %f %f %f %f %f %f %f %f', 'Delimiter', ',');
fclose(fid);
keep = strcmp(C{1}, 'file');
inputs = [C{3}(keep) C{4}(keep) C{5}(keep) C{6}(keep) zeros(sum(keep), 1) C{7}(keep) C{8}(keep)];
stored = [C{9}(keep) C{10}(keep) C{11}(keep) C{12}(keep) C{13}(keep)];
params = mfeval.readTIR('mfeval_MagicFormula61_Paramerters.tir');
solver = mfeval.Solver();
out = solver.fullSteadyState(params, inputs, 111);
got = out(:, [1 2 4 5 6]);
names = {'Fx', 'Fy', 'Mx', 'My', 'Mz'};
for j = 1:5
  printf('%s: max difference %.3g %% of peak\n', names{j}, 100 * max(abs(got(:, j) - stored(:, j))) / max(abs(stored(:, j))));
end
