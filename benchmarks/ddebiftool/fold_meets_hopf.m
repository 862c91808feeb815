function fold_meets_hopf(foldmat,hopfmat)
%% Where the fold-of-cycles curve (pofold_curve.m's .mat) runs below tau = 2:
% for each of its points, the first Hopf point at exactly the same tau
% (corrected from hopf_curve.m's curve), k_fold - k_H, the fold orbit's
% peak-to-peak m_y and the period against 2 pi/omega_H. At the Bautin point
% the fold curve must end on the Hopf curve with vanishing amplitude.
setup_path();
F=load(foldmat); H=load(hopfmat);
[~,~,funcs,ip,hbr]=hopf_point(2,8.0,false);
sel=find(F.tau<2);
for i=sel(:)'
    [h,ok]=hopf_at_tau(funcs,ip,hbr,H.curve,F.tau(i));
    fprintf('FOLDvsHOPF tau=%.6f k_fold=%.8f k_H=%.8f k_fold-k_H=%+.3e pp(m_y)=%.4e T=%.6f 2pi/omega_H=%.6f (Hopf corrected=%d)\n',...
        F.tau(i),F.k(i),h.parameter(ip.k),F.k(i)-h.parameter(ip.k),F.A(i),F.T(i),2*pi/abs(h.omega),ok);
end
end
