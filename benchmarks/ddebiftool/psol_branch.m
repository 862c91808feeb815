function [pbr,funcs,ip,hopf]=psol_branch(tau,kstart,opts)
%% branch of periodic orbits from the Hopf point at delay tau, continued in k
% opts: degree, intervals, npts, kmax, maxstep
[hopf,~,funcs,ip,hbr]=hopf_point(tau,kstart);
[pbr,suc]=SetupPsol(funcs,hbr,1,...
    'contpar',[ip.k,ip.c],'degree',opts.degree,'intervals',opts.intervals,...
    'radius',1e-3,'max_step',[ip.k,opts.maxstep],...
    'max_bound',[ip.k,opts.kmax],'min_bound',[ip.k,0.05]);
if ~suc, error('psol init failed'); end
pbr.method.continuation.plot=0;
pbr.method.point.extra_condition=1;   % activate the pinning z(0)=0 (sys_cond)
pbr.method.continuation.steplength_growth_factor=1.2;
pbr.method.point.adapt_mesh_after_correct=1;
pbr.method.point.adapt_mesh_before_correct=1;
pbr.parameter.max_step=[ip.k,opts.maxstep; 0, opts.maxstep*2];
pbr=br_contn(funcs,pbr,opts.npts);
end
